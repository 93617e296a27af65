#!/bin/sh
# Stands in for python3 ($GRANULAR_PYTHON) in tests of `granular accuracy --out`, so they run without
# matplotlib: answers yes to `-c 'import matplotlib'`, and otherwise writes the arguments it was
# given, one per line, to $GRANULAR_TEST_ARGV_FILE.
if [ "$1" = "-c" ]; then exit 0; fi
printf '%s\n' "$@" > "$GRANULAR_TEST_ARGV_FILE"
