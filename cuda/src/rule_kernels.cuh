#pragma once
/// @file rule_kernels.cuh
/// The definitions of RuleLaunch (rule_launch.cuh). Only the rule_kernels_*.cu files include this,
/// each instantiating RuleLaunch for one Rule type.

#include "granular/errors.hpp"
#include "rule_launch.cuh"

namespace granular::cuda {

template <class Rule>
void RuleLaunch<Rule>::dense(const DeviceCells& g, const Rule& rule, const StepShape& shape,
                             const ActivityRecord* record, cudaStream_t stream) {
  if (record != nullptr)
    launch_dense<OwnerNotes>(g, rule, shape, *record, stream);
  else
    launch_dense<NoNotes>(g, rule, shape, {}, stream);
}

template <class Rule>
void RuleLaunch<Rule>::pair(const DeviceCells& g, const Rule& first, const Rule& second, const PairShape& shape,
                            std::uint8_t* halo, const ActivityRecord* record, cudaStream_t stream) {
  if constexpr (Rule::kStepsSide) {
    // The pair kernel's shared tiles hold no side plane; the backend never fuses such steps.
    throw BackendError("cuda backend: the pair kernel was asked to fuse two steps of a rule set with a side plane "
                       "(MotionParams::momentum), which it does not step");
  } else if (record != nullptr)
    launch_pair<OwnerNotes>(g, first, second, shape, halo, *record, stream);
  else
    launch_pair<NoNotes>(g, first, second, shape, halo, {}, stream);
}

template <class Rule>
void RuleLaunch<Rule>::sparse(const DeviceCells& g, const Rule& rule, const SparseParams& params, bool count,
                              bool last_tick, unsigned grid, cudaStream_t stream) {
  launch_sparse(g, rule, params, count, last_tick, grid, stream);
}

template <class Rule>
unsigned RuleLaunch<Rule>::sparse_resident(int sm_count) {
  return sparse_resident_blocks<Rule>(sm_count);
}

}  // namespace granular::cuda
