#pragma once
/// @file cpu_step.hpp
/// The CPU block-stepping kernel: one tick's Margolus partition, one layer of blocks at a time.

#include <cstdint>
#include <span>
#include <vector>

#include "granular/block.hpp"
#include "granular/geometry.hpp"
#include "step/motion_block.hpp"

namespace granular {

/// What one tick of the kernel needs.
struct StepContext {
  std::uint8_t* cells = nullptr;      ///< the grid, x fastest
  Int3 size{};                        ///< grid extent
  const BlockKey* result = nullptr;   ///< 8^8 result keys: the key after the block's transition
  std::uint64_t seed = 0;             ///< world seed (random rules)
  std::uint64_t tick = 0;             ///< the tick being computed (selects the offset)
  bool random_symmetry = false;       ///< draw a horizontal symmetry per block
  bool random_axis_order = false;     ///< draw the offset order per 8-tick cycle (block_offset)
  const Transition* transitions = nullptr;  ///< the transition table (motion model only)
  bool motion = false;                ///< the rule set's motion model is on: `sub` is one of its sub-steps
  motion::SubStep sub{};              ///< the sub-step (motion model only; sub.tick == tick)
};

/// The partition offset of the context's tick (or sub-step, with the motion model).
inline BlockOffset context_offset(const StepContext& c) {
  return c.motion ? motion::motion_offset(c.tick, c.sub.substep, c.seed, c.random_axis_order)
                  : block_offset(c.tick, c.seed, c.random_axis_order);
}

/// The CPU's form of a transition table: for each key, the key of the block after its transition
/// (one lookup and an unpack instead of applying a permutation cell by cell).
std::vector<BlockKey> derive_result_table(std::span<const Transition> lut, int threads);

/// Number of block layers (along z) of the tick's partition.
int block_layers(const StepContext& context);

/// Steps every block of layer `layer` (blocks whose lowest z is 2*layer - offset.z). Layers of one
/// tick touch disjoint cells, so any set of layers may run concurrently.
void step_block_layer(const StepContext& context, int layer);

}  // namespace granular
