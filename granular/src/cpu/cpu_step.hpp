#pragma once
/// @file cpu_step.hpp
/// The CPU block-stepping kernel: one (sub-)step's Margolus partition, one layer of blocks at a time,
/// each block through the one block step (step/block_step.hpp).

#include <cstdint>
#include <span>
#include <vector>

#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"
#include "step/block_step.hpp"

namespace granular {

/// What one (sub-)step of the kernel needs.
struct StepContext {
  std::uint8_t* cells = nullptr;  ///< the grid, x fastest
  Int3 size{};                    ///< grid extent
  std::uint8_t* outside_row = nullptr;  ///< size.x cells of the outside state (rules.materials.outside),
                                        ///< what a row of cells outside the grid reads; never written
  std::uint8_t* side = nullptr;   ///< the side plane (MotionParams::momentum, momentum.hpp), laid out as
                                  ///< cells; null without (then rules.side is false)
  std::uint8_t* outside_side_row = nullptr;  ///< size.x zero bytes: the side bytes outside the grid; never written
  StepRules rules;                ///< the rule set's tables and parameters (host memory)
  std::uint64_t tick = 0;         ///< the tick being computed
  int substep = 0;                ///< its sub-step (0 without a motion model)
};

/// The partition offset of the context's (sub-)step.
inline BlockOffset context_offset(const StepContext& c) { return step_offset(c.rules, c.tick, c.substep); }

/// The CPU's form of a transition table: for each key, the key of the block after its transition
/// (one lookup and an unpack instead of applying a permutation cell by cell).
std::vector<BlockKey> derive_result_table(std::span<const Transition> lut, int threads);

/// Number of block layers (along z) of the (sub-)step's partition.
int block_layers(const StepContext& context);

/// Steps every block of layer `layer` (blocks whose lowest z is 2*layer - offset.z). Layers of one
/// (sub-)step touch disjoint cells, so any set of layers may run concurrently.
void step_block_layer(const StepContext& context, int layer);

}  // namespace granular
