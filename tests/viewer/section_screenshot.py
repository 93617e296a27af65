#!/usr/bin/env python3
"""The headless sandbox's screenshot through a section: `SANDBOX --headless --scene hourglass
--section y:0.5 --screenshot F` (small, validated) must show the sand inside the hourglass, and the
same command without the section must show none (the hourglass is closed all round). A pixel is
sand when its hue is sand's under any light: red above green above blue, blue well below red.
Exit status 0 on success, 1 with the reason otherwise.

usage: section_screenshot.py SANDBOX FOLDER
"""

import os
import subprocess
import sys

from png_pixels import read_png

ARGUMENTS = ["--headless", "--validation", "--scene", "hourglass", "--frames", "4", "--width", "480", "--height", "360"]


def sand_share(path):
    """The fraction of the image's pixels that are sand-coloured."""
    width, height, rows = read_png(path)
    sand = 0
    for row in rows:
        for x in range(0, width * 4, 4):
            r, g, b = row[x], row[x + 1], row[x + 2]
            sand += 1 if r > g > b and (r - b) * 3 > r else 0
    return sand / (width * height)


def screenshot(sandbox, folder, name, extra):
    path = os.path.join(folder, name)
    command = [sandbox, *ARGUMENTS, *extra, "--screenshot", path]
    run = subprocess.run(command, capture_output=True, text=True, timeout=300)
    sys.stdout.write(run.stdout + run.stderr)
    if run.returncode != 0 or "validation     on, 0 messages" not in run.stdout:
        sys.exit(f"FAILED: {' '.join(command)} exited {run.returncode} or reported validation messages")
    return sand_share(path)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    sandbox, folder = sys.argv[1], sys.argv[2]
    os.makedirs(folder, exist_ok=True)
    cut = screenshot(sandbox, folder, "hourglass-section.png", ["--section", "y:0.5"])
    closed = screenshot(sandbox, folder, "hourglass-closed.png", [])
    print(f"sand pixels: {cut:.2%} through the section y:0.5, {closed:.2%} without it")
    if cut < 0.01:
        print("FAILED: the screenshot through the section shows almost no sand")
        return 1
    if closed > 0.0:
        print("FAILED: the closed hourglass shows sand")
        return 1
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
