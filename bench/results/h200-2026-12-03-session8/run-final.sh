#!/usr/bin/env bash
set -u
export LD_LIBRARY_PATH=$PWD/.gpubin/lib GRANULAR_CACHE_DIR=/tmp/lut
o=/tmp/o; mkdir -p $o
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $o/gpu.txt
s=$(date +%s)
.gpubin/granular_gpu_tests > $o/gpu-tests.txt 2>&1; echo "gpu tests rc=$? in $(( $(date +%s)-s )) s" >> $o/gpu-tests.txt
for i in 1 2; do
  .gpubin/granular run --scene bowl --size 1024 --backend cuda --ticks 63 --json --no-progress > $o/bowl1024-63-default-$i.json 2>>$o/bowl.err
  .gpubin/granular run --scene bowl --size 1024 --backend cuda --ticks 250 --json --no-progress > $o/bowl1024-250-default-$i.json 2>>$o/bowl.err
done
tar czf $OUT/final.tgz -C $o .
tail -3 $o/gpu-tests.txt
