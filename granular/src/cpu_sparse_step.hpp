#pragma once
/// @file cpu_sparse_step.hpp
/// The CPU kernel of sparse stepping: one tick's blocks owned by one brick (brick_grid.hpp), with
/// what the activity tracking needs recorded on the way (docs/ARCHITECTURE.md, "Activity tracking").

#include <cstdint>

#include "cpu_step.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// Where the sparse kernel records what it saw; one byte per brick, x fastest.
struct BrickRecord {
  Int3 bricks{};                         ///< bricks per axis
  std::uint8_t* dirty = nullptr;         ///< set for a brick that owns a block with a non-inert key
                                         ///< (written only by the task stepping that brick)
  std::uint8_t* changed = nullptr;       ///< set for a brick one of whose cells changed (written by
                                         ///< several tasks, with relaxed atomic stores of 1)
};

/// Longest run of bricks step_brick_run takes.
inline constexpr int kMaxBrickRun = 32;

/// Steps the blocks of tick context.tick owned by the `length` (1..kMaxBrickRun) bricks
/// first_brick, first_brick + 1, ... (consecutive along x, one row of bricks), recording into
/// `record`. A run walks each row of cells once across all its bricks, like the dense kernel.
/// Bricks of one tick own disjoint blocks, so any set of runs may run concurrently.
void step_brick_run(const StepContext& context, const BrickRecord& record, std::uint32_t first_brick, int length);

}  // namespace granular
