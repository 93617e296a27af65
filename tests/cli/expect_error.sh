#!/bin/sh
# Usage: expect_error.sh REGEX COMMAND [ARGS...]
# Passes (exit 0) when COMMAND exits with status 1 within 60 seconds, prints nothing on stdout,
# and the last line of its stderr starts with "error: " and matches the extended regular
# expression REGEX. Prints what it saw either way.
regex=$1
shift
out=$(mktemp)
err=$(mktemp)
timeout 60 "$@" >"$out" 2>"$err"
status=$?
last=$(tail -n 1 "$err")
echo "status: $status"
echo "stderr:"
cat "$err"
ok=1
if [ "$status" -ne 1 ]; then echo "FAIL: exit status $status, expected 1"; ok=0; fi
if [ -s "$out" ]; then echo "FAIL: stdout is not empty:"; head -c 2000 "$out"; ok=0; fi
case $last in
  "error: "*) ;;
  *) echo "FAIL: the last stderr line does not start with 'error: '"; ok=0 ;;
esac
if ! printf '%s\n' "$last" | grep -Eq -- "$regex"; then echo "FAIL: the error does not match: $regex"; ok=0; fi
rm -f "$out" "$err"
[ $ok -eq 1 ] && echo PASS
[ $ok -eq 1 ]
