#pragma once
/// @file brick_activity.hpp
/// The sleep/wake state of sparse stepping, kept on the host (the CPU backend; the CUDA backend
/// keeps the same state on the device). See docs/design/sparse-stepping.md.

#include <cstdint>
#include <span>
#include <vector>

#include "cpu/cpu_sparse_step.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// Per brick: awake (stepped this cycle), dirty (owned a block with a non-inert key this cycle, or
/// touched by a tool) and changed (a cell changed since the last take_changed). At the end of every
/// 8-tick cycle the awake set becomes the dirty set grown by one brick in all 26 directions. Also
/// the passes that let a quiet brick skip a step (BrickRecord): per brick, the last pass one of its
/// cells changed in, and per brick and offset, the last pass its blocks were all quiet in.
class BrickActivity {
 public:
  /// The state of a new world of `grid_size` cells: every brick dirty and awake.
  explicit BrickActivity(Int3 grid_size);

  /// Bricks per axis.
  Int3 bricks() const { return bricks_; }
  /// A run of awake bricks consecutive along x: first, first + 1, ..., first + length - 1.
  struct Run {
    std::uint32_t first;  ///< brick index of the run's first brick
    int length;           ///< bricks in the run (1..kMaxBrickRun)
  };
  /// The awake bricks, ascending.
  const std::vector<std::uint32_t>& active() const { return active_; }
  /// The awake bricks as runs along x (for step_brick_run), ascending.
  const std::vector<Run>& runs() const { return runs_; }
  /// Cells inside the awake bricks.
  std::uint64_t active_cells() const { return active_cells_; }
  /// Starts the next pass and returns where its kernel records dirty and changed bricks. Pass
  /// numbers are 32-bit: before the count wraps, every brick's passes are forgotten.
  BrickRecord next_pass();
  /// Ends an 8-tick cycle: awake = dirty grown by one brick, then nothing is dirty.
  void end_cycle();
  /// Cells of `bricks` were overwritten from outside (tools, load): they are dirty for this cycle,
  /// they and their neighbours are awake from the next tick on, and they count as changed in the
  /// next pass.
  void wake(std::span<const std::uint32_t> bricks);
  /// Cells of `bricks` changed in a way that needs no wake (inside a carried train): they count as
  /// changed for take_changed.
  void mark_changed(std::span<const std::uint32_t> bricks);
  /// Sets flags[i] = 1 for every brick whose cells changed since the last call; clears the record.
  void take_changed(std::span<std::uint8_t> flags);
  /// The last pass started (next_pass); 0 before the first and right after the count wraps.
  std::uint32_t pass() const { return pass_; }
  /// True when a cell of some brick changed (in a pass, or by a tool's wake) after pass `pass`, or
  /// the pass count wrapped since (it forgets every brick's passes).
  bool changed_since(std::uint32_t pass) const;

 private:
  void set_neighbours_awake(std::uint32_t brick);
  void rebuild_active();

  Int3 size_;
  Int3 bricks_;
  std::vector<std::uint8_t> awake_, dirty_, changed_;
  std::uint32_t pass_ = 0;                   // the last pass started
  std::vector<std::uint32_t> changed_pass_;  // per brick (BrickRecord::changed_pass)
  std::vector<std::uint32_t> quiet_pass_;    // per brick and offset (BrickRecord::quiet_pass)
  std::vector<std::uint8_t> reach_;          // per brick (BrickRecord::reach)
  std::vector<std::uint32_t> active_;
  std::vector<Run> runs_;
  std::uint64_t active_cells_ = 0;
};

}  // namespace granular
