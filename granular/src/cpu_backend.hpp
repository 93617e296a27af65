#pragma once
/// @file cpu_backend.hpp
/// The multithreaded CPU reference backend.

#include <memory>

#include "backend.hpp"
#include "granular/grid.hpp"
#include "granular/lut.hpp"
#include "thread_pool.hpp"

namespace granular {

/// Steps a byte-per-cell grid on the CPU. Within a tick all blocks are disjoint, so block layers
/// are shared out among threads freely: the result never depends on the thread count.
class CpuBackend final : public Backend {
 public:
  /// Takes a copy of `initial`; `threads` >= 1. The flags are the rule set's (RuleSet).
  CpuBackend(const Grid& initial, std::shared_ptr<const Lut> lut, bool random_symmetry, bool random_axis_order,
             std::uint64_t seed, int threads);

  BackendKind kind() const override { return BackendKind::Cpu; }
  std::string description() const override;
  void step(std::uint64_t first_tick, int ticks) override;
  void read(const Box& box, std::span<std::uint8_t> out) const override;
  void write(const Box& box, std::span<const std::uint8_t> in) override;
  MaterialCounts count() const override;
  std::uint64_t hash() const override;

 private:
  void step_tick(std::uint64_t tick);

  Grid grid_;
  std::shared_ptr<const Lut> lut_;
  std::shared_ptr<const std::vector<BlockKey>> result_;
  bool random_symmetry_;
  bool random_axis_order_;
  std::uint64_t seed_;
  mutable ThreadPool pool_;
};

}  // namespace granular
