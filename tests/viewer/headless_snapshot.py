#!/usr/bin/env python3
"""The headless sandbox saves and loads snapshots that continue bit-identically: a run of N frames
saved with --save, loaded with --load and run on until tick T prints the same "saved: FILE (C cells,
tick T, hash H)" state as one run that went to tick T without stopping; the load prints the state
the save printed. Exit status 0 on success, 1 with the reason otherwise.

usage: headless_snapshot.py SANDBOX FOLDER"""

import os
import re
import subprocess
import sys

COMMON = ["--headless", "--width", "160", "--height", "120", "--renderer", "raymarch", "--ticks-per-frame", "2"]
STATE = r"\((\d+) cells, tick (\d+), hash ([0-9a-f]{16})\)"


def run(sandbox, args, what):
    """Runs the sandbox; returns {"saved": state, "loaded": state} from the lines it printed."""
    result = subprocess.run([sandbox, *COMMON, *args], capture_output=True, text=True, timeout=300)
    sys.stdout.write(result.stdout)
    if result.returncode != 0:
        raise RuntimeError(f"{what} exited with status {result.returncode}: {result.stderr.strip()}")
    states = {}
    for kind in ("saved", "loaded"):
        match = re.search(rf"^{kind}: .* {STATE}$", result.stdout, re.M)
        if match:
            states[kind] = match.groups()
    return states


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    sandbox, folder = sys.argv[1], sys.argv[2]
    os.makedirs(folder, exist_ok=True)
    half, rest, whole = (os.path.join(folder, name) for name in ("half.gsnap", "REST.GSNAP", "whole.gsnap"))
    try:
        first = run(sandbox, ["--scene", "dam_break", "--size", "24", "--frames", "8", "--save", half], "the first half")
        second = run(sandbox, ["--load", half, "--frames", "9", "--save", rest], "the second half")
        if second.get("loaded") != first.get("saved"):
            raise RuntimeError(f"--load printed {second.get('loaded')}, but --save printed {first.get('saved')}")
        ticks = int(second["saved"][1])
        # Frame 1 shows the starting state, each later frame runs one fixed update of 2 ticks.
        one = run(sandbox, ["--scene", "dam_break", "--size", "24", "--frames", str(ticks // 2 + 1), "--save", whole],
                  "the whole run")
        if one.get("saved") != second.get("saved"):
            raise RuntimeError(f"saved and continued: {second.get('saved')}; one run: {one.get('saved')}")
    except (RuntimeError, KeyError, subprocess.TimeoutExpired) as failure:
        print(f"FAILED: {failure}", flush=True)
        return 1
    print(f"PASSED: tick {one['saved'][1]}, hash {one['saved'][2]} both ways", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
