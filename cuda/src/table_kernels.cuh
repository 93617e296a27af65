#pragma once
/// @file table_kernels.cuh
/// Device kernels over the 16,777,216 block keys: the transition tables of the device rules
/// (RuleSet::device_rule "paper" and "motion"), and the result table (per key, the key after its transition) that the step kernel looks up.
/// Kernels and launchers here are static: every translation unit including this gets its own copy.

#include <cuda_runtime.h>

#include <cstdint>

#include "cuda_check.cuh"
#include "granular/extend/block.hpp"
#include "step/fluid_block.hpp"
#include "step/motion_block.hpp"
#include "step/step_materials.hpp"

namespace granular::cuda {

/// Threads per CUDA block of the table kernels.
inline constexpr int kTableThreads = 256;

/// out[k] = the one-step transition of k (fluid::one_step_transition: gravity and flow, then the fluid
/// pass): the very function the CPU's "paper" rule evaluates, on the material table `materials`.
static __global__ void paper_lut_kernel(Transition* out, StepMaterials materials) {
  const std::uint32_t key = blockIdx.x * blockDim.x + threadIdx.x;
  if (key < kBlockKeyCount) out[key] = fluid::one_step_transition(key, materials);
}

/// out[k] = motion::motion_rule(k): the very function the CPU's motion rule sets evaluate.
static __global__ void motion_lut_kernel(Transition* out) {
  const std::uint32_t key = blockIdx.x * blockDim.x + threadIdx.x;
  if (key < kBlockKeyCount) out[key] = motion::motion_rule(key);
}

/// result[k] = encode_key(apply_transition(decode_key(k), lut[k])), as the CPU's derive_result_table.
static __global__ void result_table_kernel(const Transition* lut, BlockKey* result) {
  const std::uint32_t key = blockIdx.x * blockDim.x + threadIdx.x;
  if (key < kBlockKeyCount) result[key] = encode_key(apply_transition(decode_key(key), lut[key]));
}

/// Enqueues paper_lut_kernel over all keys into `out` (kBlockKeyCount entries).
static inline void launch_paper_lut(Transition* out, const StepMaterials& materials, cudaStream_t stream) {
  paper_lut_kernel<<<kBlockKeyCount / kTableThreads, kTableThreads, 0, stream>>>(out, materials);
  check_launch("transition table kernel launch");
}

/// Enqueues motion_lut_kernel over all keys into `out` (kBlockKeyCount entries).
static inline void launch_motion_lut(Transition* out, cudaStream_t stream) {
  motion_lut_kernel<<<kBlockKeyCount / kTableThreads, kTableThreads, 0, stream>>>(out);
  check_launch("motion transition table kernel launch");
}

/// Enqueues result_table_kernel over all keys (`lut` and `result` hold kBlockKeyCount entries).
static inline void launch_result_table(const Transition* lut, BlockKey* result, cudaStream_t stream) {
  result_table_kernel<<<kBlockKeyCount / kTableThreads, kTableThreads, 0, stream>>>(lut, result);
  check_launch("result table kernel launch");
}

}  // namespace granular::cuda
