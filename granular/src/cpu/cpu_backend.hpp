#pragma once
/// @file cpu_backend.hpp
/// The multithreaded CPU reference backend.

#include <memory>
#include <optional>

#include "cpu/brick_activity.hpp"
#include "cpu/cpu_head_field.hpp"
#include "cpu/cpu_shallow_pass.hpp"
#include "cpu/cpu_step.hpp"
#include "granular/extend/backend.hpp"
#include "granular/extend/backend_factory.hpp"
#include "granular/grid.hpp"
#include "granular/extend/lut.hpp"
#include "granular/task_system.hpp"

namespace granular {

/// Steps a byte-per-cell grid on the CPU. Within a tick all blocks are disjoint, so block layers
/// are shared out among threads freely: the result never depends on the thread count.
class CpuBackend final : public Backend {
 public:
  /// Takes a copy of info.initial and steps it with info.lut, the table of info.rules (its random
  /// flags and motion model); info.sparse steps only the awake bricks. Every parallel loop runs on
  /// info.task_system, or on a ThreadPool of info.threads (>= 1) threads when that is null. The
  /// checks are make_cpu_backend's.
  explicit CpuBackend(const BackendCreateInfo& info);

  BackendKind kind() const override { return BackendKind::Cpu; }
  std::string description() const override;
  void step(std::uint64_t first_tick, int ticks) override;
  void read(const Box& box, std::span<std::uint8_t> out) const override;
  void write(const Box& box, std::span<const std::uint8_t> in, std::span<const std::uint32_t> wake_bricks) override;
  MaterialCounts count() const override;
  std::uint64_t hash() const override;
  std::vector<std::uint8_t> read_side() const override;
  void write_side(std::span<const std::uint8_t> side) override;
  std::vector<std::int32_t> read_faces() const override;
  void write_faces(std::span<const std::int32_t> faces) override;
  void take_changed_bricks(std::span<std::uint8_t> flags) override;
  ActivityStats last_activity() const override { return last_; }
  /// A host copy of the cells.
  void take_checkpoint() override;
  void read_checkpoint(const Box& box, std::span<std::uint8_t> out) const override;
  void drop_checkpoint() override;
  std::uint64_t checkpoint_bytes() const override { return checkpoint_.size(); }
  TaskSystem* host_tasks() override { return &pool_; }

 private:
  // Copies the cells of `box` from `cells` (this grid's layout) into `out`, x fastest.
  void copy_box(const std::uint8_t* cells, const Box& box, std::span<std::uint8_t> out) const;
  /// Before a tick under MotionParams::pressure: StepRules::heads (null without liquid), the heads
  /// solved when they may have changed, and the bricks where a pressure move may start woken.
  void prepare_heads();
  /// Closes the trains of the grid after a tick (MotionParams::trains) and wakes the bricks they changed.
  void close_tick_trains();
  /// Runs the shallow-water pass after a tick (MotionParams::shallow) unless it is at rest on
  /// unchanged cells, and wakes the bricks it changed.
  void run_shallow_pass();
  /// Liquid cells among `cells` (the rule set's liquids).
  std::uint64_t liquid_in(std::span<const std::uint8_t> cells) const;
  /// Liquid cells of the grid inside `box`.
  std::uint64_t liquid_in(const Box& box) const;
  StepContext context(std::uint64_t tick, int substep);
  void step_pass(const StepContext& c);
  void step_pass_sparse(const StepContext& c);

  Grid grid_;
  std::vector<std::uint8_t> checkpoint_;  ///< the cells at take_checkpoint(); empty when there is none
  std::shared_ptr<const Lut> lut_;
  std::shared_ptr<const std::vector<BlockKey>> result_;  ///< per key, the key after its transition (one-step rule sets)
  bool sparse_;
  std::shared_ptr<const std::vector<std::uint64_t>> inert_;  ///< inert-key bits (sparse, random symmetry or motion)
  std::vector<motion::MotionEntry> motion_table_;  ///< the motion entries (motion rule sets; motion_table.hpp)
  StepRules step_rules_;  ///< the tables and parameters every step's Rule is made from
  std::vector<std::uint8_t> outside_row_;  ///< a row of cells outside the grid (StepContext::outside_row)
  BrickActivity activity_;
  std::optional<CpuHeadField> head_field_;  ///< MotionParams::pressure with a liquid in the table: the heads
  bool heads_solved_ = false;                ///< head_field_ holds the heads of the cells of activity_'s pass
                                             ///< heads_pass_ (sparse stepping; a write clears it)
  std::uint32_t heads_pass_ = 0;             ///< the pass the heads were last solved after
  std::vector<std::uint32_t> pressing_;      ///< the bricks the last solve found a pressure move may start in
  std::uint64_t liquid_cells_ = 0;           ///< liquid cells of the grid (head_field_ or shallow_ only; writes
                                             ///< update it)
  std::optional<CpuShallowPass> shallow_;    ///< MotionParams::shallow with a liquid in the table: the face plane
  bool shallow_rest_ = false;                ///< the pass was at rest on the cells of activity_'s pass
                                             ///< shallow_pass_ (sparse stepping; a write clears it)
  std::uint32_t shallow_pass_ = 0;           ///< the pass the shallow-water pass last ran after
  std::vector<std::uint8_t> side_;           ///< the side plane (MotionParams::momentum with a liquid in the table;
                                             ///< else empty), laid out as the cells
  std::vector<std::uint8_t> outside_side_row_;  ///< a row of zero side bytes (StepContext::outside_side_row)
  ActivityStats last_{};
  std::shared_ptr<TaskSystem> task_system_;  ///< info.task_system, or the backend's own ThreadPool
  TaskSystem& pool_;                         ///< *task_system_: runs every parallel loop
};

}  // namespace granular
