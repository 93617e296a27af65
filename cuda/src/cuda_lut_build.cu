#include <cuda_runtime.h>

#include <string>
#include <vector>

#include "cuda_check.cuh"
#include "cuda_device.cuh"
#include "cuda_stream.cuh"
#include "device_buffer.cuh"
#include "granular/errors.hpp"
#include "granular_cuda/cuda_backend_factory.hpp"
#include "table_kernels.cuh"

namespace granular {

std::vector<Transition> build_lut_on_gpu(const RuleSet& rules, float* kernel_ms) {
  const bool motion = rules.device_rule == "motion";
  if (rules.device_rule != "paper" && !motion)
    throw InvalidArgument("build_lut_on_gpu: rule set '" + rules.name + "' has device rule '" + rules.device_rule +
                          "'; only \"paper\" and \"motion\" are compiled for GPUs");
  cuda::acquire_device();
  cuda::Stream stream;
  cuda::DeviceBuffer<Transition> table(kBlockKeyCount, "the transition table");
  cuda::Event start, stop;
  start.record(stream.get());
  if (motion)
    cuda::launch_motion_lut(table.data(), stream.get());
  else
    cuda::launch_paper_lut(table.data(), step_materials(rules.materials), stream.get());
  stop.record(stream.get());
  stream.synchronize("building the transition table");
  const float ms = stop.ms_since(start);
  if (kernel_ms != nullptr) *kernel_ms = ms;
  std::vector<Transition> entries(kBlockKeyCount);
  cuda::check(cudaMemcpyAsync(entries.data(), table.data(), table.bytes(), cudaMemcpyDeviceToHost, stream.get()),
              "cudaMemcpyAsync (transition table)");
  stream.synchronize("copying the transition table");
  return entries;
}

}  // namespace granular
