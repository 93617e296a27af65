source .gpubin/env.sh
printf '{"file_format_version":"1.0.0","ICD":{"library_path":"libEGL_nvidia.so.0","api_version":"1.3.0"}}\n' > /tmp/icd_egl.json
export VK_ICD_FILENAMES=/tmp/icd_egl.json GRANULAR_SHADER_DIR=$PWD/.gpubin/spv
b=.gpubin/bench_viewer
run() { echo "== $*"; timeout 120 $b --backend cuda --warmup 10 --csv $OUT/lod.csv "$@" 2>&1 | grep -vE "^$" | tail -1; }
for c in 0 1 1.5 2; do
run --size 512 --frames 20 --renderers marching --ticks-per-frame 0 --coarse-below $c
run --size 1024 --frames 20 --renderers marching --ticks-per-frame 0 --coarse-below $c
done
for c in 1 1.5; do
run --size 512 --real-time --frames 300 --renderers marching --coarse-below $c
run --size 1024 --real-time --frames 120 --renderers marching --coarse-below $c
done
