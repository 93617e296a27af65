#!/usr/bin/env python3
"""README's table of the sandbox's controls is the sandbox's own (viewer/src/window/controls.hpp, the table
the HUD lists): the same rows in the same order, so README offers no key the sandbox lacks and
lists every one it has."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    source = open(os.path.join(ROOT, "viewer", "src", "window", "controls.hpp")).read()
    controls = re.findall(r'\{"((?:[^"\\]|\\.)*)", "((?:[^"\\]|\\.)*)"\}', source)
    readme = open(os.path.join(ROOT, "README.md")).read()
    table = readme[readme.index("| input | action |"):]
    rows = []
    for line in table.splitlines()[2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        rows.append((cells[0], cells[1]))
    # README escapes the | of a cell as \|.
    rows = [(a.replace("\\|", "|"), b.replace("\\|", "|")) for a, b in rows]
    if not controls:
        sys.exit("readme_controls: no controls found in viewer/src/window/controls.hpp")
    if rows != controls:
        for i in range(max(len(rows), len(controls))):
            a = rows[i] if i < len(rows) else None
            b = controls[i] if i < len(controls) else None
            if a != b:
                print(f"readme_controls: row {i + 1}: README {a} but controls.hpp {b}")
        sys.exit(1)
    print(f"readme_controls: README lists the sandbox's {len(rows)} controls")


if __name__ == "__main__":
    main()
