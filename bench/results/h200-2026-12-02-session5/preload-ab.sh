source .gpubin/env.sh
printf '{"file_format_version":"1.0.0","ICD":{"library_path":"libEGL_nvidia.so.0","api_version":"1.3.0"}}\n' > /tmp/icd_egl.json
export VK_ICD_FILENAMES=/tmp/icd_egl.json
b=.gpubin/bench_viewer_new
for r in 1; do for v in new pre; do export GRANULAR_SHADER_DIR=$PWD/.gpubin/ab/$v
echo -n "$v "; timeout 100 $b --backend cuda --warmup 10 --size 1024 --frames 40 --renderers marching --ticks-per-frame 1 --csv $OUT/preload-ab.csv 2>&1 | tail -1
done; done
export GRANULAR_SHADER_DIR=$PWD/.gpubin/ab/pre
run() { echo "== $*"; timeout 150 $b --backend cuda --warmup 10 --csv $OUT/final2.csv "$@" 2>&1 | grep -vE "^$" | tail -1; }
run --size 512 --real-time --frames 60 --renderers marching
run --size 1024 --real-time --frames 60 --renderers marching
run --size 1024 --real-time --frames 1000 --renderers marching
export VK_LAYER_PATH=/opt/deps/usr/share/vulkan/explicit_layer.d GRANULAR_SHADER_DIR=$PWD/.gpubin/spv
timeout 200 .gpubin/granular_viewer_tests --duration=true > $OUT/viewer-tests.log 2>&1; echo "viewer tests rc $?"
grep -E "test cases|assertions|ERROR|FAILED" $OUT/viewer-tests.log | head -12
timeout 100 .gpubin/granular_viewer_interop_tests --duration=true > $OUT/interop-tests.log 2>&1; echo "interop rc $?"
grep -E "test cases|assertions|ERROR" $OUT/interop-tests.log | head -8
