#pragma once
/// @file rule_launch.cuh
/// The launches of the step kernels of one Rule type (block_step.hpp's with_rule_type), as the
/// backend calls them. They are declared here and defined in rule_kernels.cuh, which one file per
/// Rule type instantiates (rule_kernels_*.cu): nvcc compiles each Rule type's kernels apart, in
/// parallel, and the backend's own file holds none of them.

#include <cuda_runtime.h>

#include <cstdint>

#include "activity_record.cuh"
#include "block_walk.cuh"
#include "pair_kernel.cuh"
#include "sparse_kernel.cuh"

namespace granular::cuda {

/// The step kernels of `Rule`, each launch checked (BackendError), not its completion.
template <class Rule>
struct RuleLaunch {
  /// One (sub-)step of `rule` over every block (launch_dense): recording the sparse flags into
  /// `*record` (OwnerNotes) when `record` is not null.
  static void dense(const DeviceCells& g, const Rule& rule, const StepShape& shape, const ActivityRecord* record,
                    cudaStream_t stream);
  /// Two pairable (sub-)steps in one pass (launch_pair), recording as dense(); a Rule that steps a
  /// side plane (Rule::kStepsSide) is never fused, and throws BackendError.
  static void pair(const DeviceCells& g, const Rule& first, const Rule& second, const PairShape& shape,
                   std::uint8_t* halo, const ActivityRecord* record, cudaStream_t stream);
  /// One sparse (sub-)step over the awake bricks (launch_sparse).
  static void sparse(const DeviceCells& g, const Rule& rule, const SparseParams& params, bool count, bool last_tick,
                     unsigned grid, cudaStream_t stream);
  /// The CUDA blocks of the sparse kernel a device of `sm_count` multiprocessors runs at once
  /// (sparse_resident_blocks).
  static unsigned sparse_resident(int sm_count);
};

}  // namespace granular::cuda
