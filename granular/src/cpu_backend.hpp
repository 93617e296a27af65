#pragma once
/// @file cpu_backend.hpp
/// The multithreaded CPU reference backend.

#include <memory>

#include "backend.hpp"
#include "brick_activity.hpp"
#include "granular/grid.hpp"
#include "granular/lut.hpp"
#include "thread_pool.hpp"

namespace granular {

/// Steps a byte-per-cell grid on the CPU. Within a tick all blocks are disjoint, so block layers
/// are shared out among threads freely: the result never depends on the thread count.
class CpuBackend final : public Backend {
 public:
  /// Takes a copy of `initial`; `threads` >= 1. `rules` is the rule set `lut` was built from (its
  /// random flags and motion model); `sparse` steps only the awake bricks.
  CpuBackend(const Grid& initial, std::shared_ptr<const Lut> lut, const RuleSet& rules, std::uint64_t seed, int threads,
             bool sparse);

  BackendKind kind() const override { return BackendKind::Cpu; }
  std::string description() const override;
  void step(std::uint64_t first_tick, int ticks) override;
  void read(const Box& box, std::span<std::uint8_t> out) const override;
  void write(const Box& box, std::span<const std::uint8_t> in) override;
  MaterialCounts count() const override;
  std::uint64_t hash() const override;
  void wake(std::span<const std::uint32_t> bricks) override;
  void take_changed_bricks(std::span<std::uint8_t> flags) override;
  ActivityStats last_activity() const override { return last_; }

 private:
  StepContext context(std::uint64_t tick, int substep);
  void step_pass(const StepContext& c);
  void step_pass_sparse(const StepContext& c);

  Grid grid_;
  std::shared_ptr<const Lut> lut_;
  std::shared_ptr<const std::vector<BlockKey>> result_;
  bool random_symmetry_;
  bool random_axis_order_;
  MotionParams motion_;
  std::uint64_t seed_;
  bool sparse_;
  std::shared_ptr<const std::vector<std::uint64_t>> inert_;  ///< inert-key bits (sparse, random symmetry or motion)
  BrickActivity activity_;
  ActivityStats last_{};
  mutable ThreadPool pool_;
};

}  // namespace granular
