#!/usr/bin/env bash
# Usage: distributed_hash.sh WORK CLI SPLIT [LAUNCHER...] -- RUN_ARGS...
# Runs `CLI run RUN_ARGS` on one domain and `[LAUNCHER...] CLI run RUN_ARGS SPLIT` (SPLIT, split at
# spaces: "--domains 3", or "--distributed" under LAUNCHER = mpiexec -n R ...), each saving a snapshot
# in WORK, and passes (exit 0) only when both print the same `checksum` line, the split run prints
# its `split` line, and the two snapshots hold the same world: the split one in format version 3
# (today's; a zstd frame per slab), each continued 3 ticks to the same checksum. Prints what it saw either way.
set -u
work=$1 cli=$2 split=$3
shift 3
launcher=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do launcher+=("$1"); shift; done
[ $# -gt 0 ] || { echo "FAIL: usage: distributed_hash.sh WORK CLI SPLIT [LAUNCHER...] -- RUN_ARGS..."; exit 2; }
shift
rm -rf "$work" && mkdir -p "$work" || exit 1
# shellcheck disable=SC2086  # SPLIT is several words on purpose
plain=$("$cli" run "$@" --no-progress --save "$work/plain.gsnap" 2>"$work/plain.err")
plain_status=$?
split_out=$("${launcher[@]}" "$cli" run "$@" $split --no-progress --save "$work/split.gsnap" 2>"$work/split.err")
split_status=$?
echo "one domain (exit $plain_status):"
printf '%s\n' "$plain"
echo "split: ${launcher[*]} granular run ... $split (exit $split_status):"
printf '%s\n' "$split_out"
ok=1
if [ $plain_status -ne 0 ] || [ $split_status -ne 0 ]; then
  echo "FAIL: a run failed"; cat "$work/plain.err" "$work/split.err"; ok=0
fi
a=$(printf '%s\n' "$plain" | grep '^checksum ')
b=$(printf '%s\n' "$split_out" | grep '^checksum ')
if [ -z "$a" ] || [ "$a" != "$b" ]; then echo "FAIL: the checksums differ: '$a' (one domain) and '$b' (split)"; ok=0; fi
if ! printf '%s\n' "$split_out" | grep -q '^split '; then echo "FAIL: the split run printed no split line"; ok=0; fi
version=$(od -An -tu4 -j4 -N4 "$work/split.gsnap" 2>/dev/null | tr -d ' ')
if [ "$version" != 3 ]; then echo "FAIL: the split snapshot's version is '$version', not 3 (a frame per slab, the header hashed)"; ok=0; fi
c=$("$cli" run --scene "$work/plain.gsnap" --ticks 3 --no-progress 2>&1 | grep '^checksum ')
d=$("$cli" run --scene "$work/split.gsnap" --ticks 3 --no-progress 2>&1 | grep '^checksum ')
if [ -z "$c" ] || [ "$c" != "$d" ]; then echo "FAIL: the snapshots continue to '$c' (one domain) and '$d' (split)"; ok=0; fi
[ $ok -eq 1 ] && echo "PASS: same $a, snapshots that continue alike ($c)"
[ $ok -eq 1 ]
