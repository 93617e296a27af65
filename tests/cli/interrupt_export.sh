#!/bin/sh
# Usage: interrupt_export.sh GRANULAR DIR
# Starts exports of ever larger grids and sends SIGTERM while the temporary file of the save
# exists (before it is renamed to the output). Passes when the export dies of SIGTERM and leaves
# neither the temporary nor an output file.
cli=$1
dir=$2
mkdir -p "$dir" || exit 1
for size in 256 320 400 480; do
  rm -f "$dir"/big.raw "$dir"/big.raw.tmp-*
  "$cli" export --scene bowl --size $size --ticks 0 --rules paper --no-progress --out "$dir/big.raw" >/dev/null 2>&1 &
  pid=$!
  tmp="$dir/big.raw.tmp-$pid"
  while [ ! -e "$tmp" ] && kill -0 "$pid" 2>/dev/null; do :; done
  if [ ! -e "$tmp" ]; then
    wait "$pid"
    echo "size $size: the export ended before its temporary file was seen; trying a larger grid"
    continue
  fi
  kill -TERM "$pid"
  wait "$pid"
  status=$?
  if [ -e "$dir/big.raw" ]; then
    echo "size $size: the save completed before SIGTERM arrived (status $status); trying a larger grid"
    continue
  fi
  echo "size $size: SIGTERM during the save, exit status $status"
  if [ "$status" -ne 143 ]; then echo "FAIL: expected death by SIGTERM (status 143)"; exit 1; fi
  if ls "$dir"/big.raw.tmp-* >/dev/null 2>&1; then echo "FAIL: the temporary file was left:"; ls -l "$dir"; exit 1; fi
  echo PASS
  exit 0
done
echo "FAIL: no export could be interrupted during its save"
exit 1
