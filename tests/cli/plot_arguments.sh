#!/bin/sh
# Usage: plot_arguments.sh GRANULAR WORKDIR
# `granular accuracy --out DIR` hands DIR to the plot script's python as an argument, never through a
# shell: a folder named like a shell command (quotes, ';') runs nothing, and a folder whose name
# holds a quote ("Bob's runs") or starts with '-' gets accuracy.json and the plot script's call with
# exactly that folder. python is tests/cli/record_python.sh, which records its arguments.
cli=$1
work=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
export GRANULAR_PYTHON="$here/record_python.sh"
export GRANULAR_TEST_ARGV_FILE="$work/argv.txt"
ok=1
for out in "o'; touch PWNED; echo '" "Bob's runs" "-dash"; do
  rm -f argv.txt
  if ! "$cli" accuracy --quick --rules paper --tests fall --threads 2 "--out=$out" > /dev/null 2> err.txt; then
    echo "FAIL: --out \"$out\" exited non-zero:"; cat err.txt; ok=0; continue
  fi
  if [ -e PWNED ]; then echo "FAIL: --out \"$out\" ran a shell command (PWNED exists)"; ok=0; fi
  if [ ! -s "$out/accuracy.json" ]; then echo "FAIL: --out \"$out\": no accuracy.json in the folder"; ok=0; fi
  expected=$(printf '%s\n' "--out=$out" -- "$out/accuracy.json")
  got=$(tail -n 3 argv.txt 2> /dev/null)
  if [ "$got" != "$expected" ]; then
    echo "FAIL: --out \"$out\": the plot script got:"; cat argv.txt; echo "expected its last arguments:"; echo "$expected"; ok=0
  else
    echo "ok: --out \"$out\""
  fi
done
[ $ok -eq 1 ] && echo PASS
[ $ok -eq 1 ]
