source .gpubin/env.sh
printf '{"file_format_version":"1.0.0","ICD":{"library_path":"libEGL_nvidia.so.0","api_version":"1.3.0"}}\n' > /tmp/icd_egl.json
export VK_ICD_FILENAMES=/tmp/icd_egl.json
run() { echo "== $*"; timeout 120 "$@" --backend cuda --warmup 10 --csv $OUT/idx.csv 2>&1 | grep -vE "^$" | tail -1; }
for rep in 1 2; do
for v in lod idx; do
  if [ $v = lod ]; then b=.gpubin/bench_viewer_lod; export GRANULAR_SHADER_DIR=$PWD/.gpubin/spv_lod; else b=.gpubin/bench_viewer; export GRANULAR_SHADER_DIR=$PWD/.gpubin/spv; fi
  for c in 0 1; do
    run $b --size 512 --frames 20 --renderers marching --ticks-per-frame 0 --coarse-below $c
    run $b --size 1024 --frames 20 --renderers marching --ticks-per-frame 0 --coarse-below $c
  done
  [ $rep = 1 ] && run $b --size 512 --real-time --frames 300 --renderers marching --coarse-below 1
  [ $rep = 1 ] && run $b --size 1024 --real-time --frames 120 --renderers marching --coarse-below 1
done; done
