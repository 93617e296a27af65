#!/usr/bin/env bash
set -u
export LD_LIBRARY_PATH=$PWD/.gpubin/lib GRANULAR_CACHE_DIR=/tmp/lut
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader > $OUT/gpu.txt
T=cone,cone_sizes,gravel_cone,hysteresis,dug_slope,silo,collapse,fall,falling_block,communicating_vessels,dam_break,torricelli,buoyancy
s=$(date +%s)
.gpubin/granular accuracy --rules inertial-24-flow --tests $T --backend cuda --threads 0 --json > $OUT/full-cuda-flow.json 2> $OUT/acc.err
echo "accuracy $(( $(date +%s)-s )) s" >> $OUT/times.txt
s=$(date +%s)
.gpubin/granular_gpu_tests > $OUT/gpu-tests.txt 2>&1; echo "gpu tests rc=$?" >> $OUT/gpu-tests.txt
echo "gpu tests $(( $(date +%s)-s )) s" >> $OUT/times.txt
for i in 1 2; do for r in inertial-24-entrain inertial-24-flow; do
  .gpubin/granular run --scene bowl --size 1024 --rules $r --backend cuda --ticks 63 --json --no-progress > $OUT/bowl1024-63-$r-$i.json 2>>$OUT/bowl.err
done; done
echo "bowl done $(( $(date +%s)-s )) s" >> $OUT/times.txt
s=$(date +%s)
.gpubin/granular accuracy --rules inertial-24-flow --tests conservation --backend cuda --threads 0 --json > $OUT/full-cuda-flow-conservation.json 2> $OUT/cons.err
echo "conservation $(( $(date +%s)-s )) s" >> $OUT/times.txt
