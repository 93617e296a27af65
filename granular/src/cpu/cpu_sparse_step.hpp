#pragma once
/// @file cpu_sparse_step.hpp
/// The CPU kernel of sparse stepping: one tick's blocks owned by one brick (brick_grid.hpp), with
/// what the activity tracking needs recorded on the way (docs/design/sparse-stepping.md).

#include <cstdint>

#include "cpu/cpu_step.hpp"
#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// Where the sparse kernel records what it saw, per brick (x fastest), and the pass it runs.
/// Passes (the sparse steps a backend ran, counted from 1) let a brick skip a step: when every block
/// it owned at an offset was quiet in pass m, and no cell its blocks touch (its footprint, inside
/// itself and the 7 bricks below it along x, y and z) changed in a later pass, its blocks at that
/// offset hold the same bytes now. A Rule's quiet() depends on a block's bytes and offset only, and
/// a quiet block stays as it is (block_step.hpp), so stepping them would change and record nothing.
/// Cells changed in pass m itself by other bricks lie outside this brick's blocks of pass m.
struct BrickRecord {
  Int3 bricks{};                         ///< bricks per axis
  std::uint8_t* dirty = nullptr;         ///< set for a brick that owns a block with a non-inert key
                                         ///< (written only by the task stepping that brick)
  std::uint8_t* changed = nullptr;       ///< set for a brick one of whose cells changed (written by
                                         ///< several tasks, with relaxed atomic stores of 1)
  std::uint32_t pass = 0;                ///< the pass being run (>= 1)
  std::uint32_t* changed_pass = nullptr; ///< per brick: the last pass in which one of its cells changed,
                                         ///< or later (0: none; relaxed atomic loads and stores)
  std::uint32_t* quiet_pass = nullptr;   ///< per brick and offset (8 a brick, offset_index): the last
                                         ///< pass at that offset in which all its blocks were quiet (0:
                                         ///< none; used only by the task stepping that brick)
  std::uint8_t* reach = nullptr;         ///< per brick: its reach in the tick under a motion model
                                         ///< (brick_reach.hpp; written by the task stepping that
                                         ///< brick, read by others: relaxed atomic loads and stores)
};

/// The index (0..7) of a partition offset in BrickRecord::quiet_pass.
constexpr int offset_index(BlockOffset o) { return o.x | (o.y << 1) | (o.z << 2); }

/// Longest run of bricks step_brick_run takes.
inline constexpr int kMaxBrickRun = 32;

/// Steps the blocks of tick context.tick owned by the `length` (1..kMaxBrickRun) bricks
/// first_brick, first_brick + 1, ... (consecutive along x, one row of bricks), recording into
/// `record`. A run walks each row of cells once across all its bricks, like the dense kernel, and
/// leaves out the bricks the record lets skip and, under a motion model, the dirty bricks that are
/// idle (brick_reach.hpp). Bricks of one tick own disjoint blocks, so any set
/// of runs may run concurrently.
void step_brick_run(const StepContext& context, const BrickRecord& record, std::uint32_t first_brick, int length);

}  // namespace granular
