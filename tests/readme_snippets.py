#!/usr/bin/env python3
"""README's code snippets are the examples' code: every ```cpp block that README introduces with
"From [`examples/...`]" must consist of lines of that file, in the file's order (comments and
indentation aside), so a snippet a user copies is code that builds and runs as a test."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def code(line):
    """The line without its // comment and with runs of whitespace made one space."""
    return " ".join(re.sub(r"//.*$", "", line).split())


def main():
    text = open(os.path.join(ROOT, "README.md")).read()
    failures, checked = [], 0
    for m in re.finditer(r"From \[`([^`]+)`\]\([^)]*\):\s*\n\s*```cpp\n(.*?)```", text, re.S):
        path, snippet = m.group(1), m.group(2)
        source = [code(l) for l in open(os.path.join(ROOT, path))]
        at = 0
        for line in snippet.splitlines():
            wanted = code(line)
            if not wanted:
                continue
            try:
                at = source.index(wanted, at) + 1
            except ValueError:
                failures.append(f"{path}: README's line `{line.strip()}` is not in the file (after line {at})")
        checked += 1
    if checked == 0:
        failures.append("README.md has no snippet introduced by From [`examples/...`]")
    for f in failures:
        print("readme_snippets:", f)
    if failures:
        sys.exit(1)
    print(f"readme_snippets: {checked} snippets are the examples' code")


if __name__ == "__main__":
    main()
