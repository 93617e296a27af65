#pragma once
/// @file granular_subsystem.hpp
/// Plugs a granular::World into the EngineLoop (target granular::engine_granular).

#include <cstdint>

#include "engine/subsystem.hpp"
#include "granular/world.hpp"

namespace engine {

/// A Subsystem that steps a granular::World a fixed number of cellular-automaton ticks on every
/// fixed update. The world is borrowed and must outlive this object.
class GranularSubsystem final : public Subsystem {
 public:
  /// Wraps `world`, stepping it `ticks_per_fixed_update` (>= 1, std::invalid_argument
  /// otherwise) ticks per fixed_update.
  explicit GranularSubsystem(granular::World& world, int ticks_per_fixed_update = 1);

  /// Calls world().step(ticks_per_fixed_update()) and times it with the steady clock. `dt` is
  /// not used: the automaton has no time unit, one fixed update is always the same ticks.
  void fixed_update(double dt) override;

  /// The wrapped world.
  granular::World& world() noexcept { return world_; }
  /// The wrapped world.
  const granular::World& world() const noexcept { return world_; }
  /// World ticks per fixed update.
  int ticks_per_fixed_update() const noexcept { return ticks_per_fixed_update_; }
  /// Changes the world ticks per fixed update (>= 1, std::invalid_argument otherwise).
  void set_ticks_per_fixed_update(int ticks);
  /// Wall-clock seconds the latest world step took (0 before the first fixed update).
  double last_step_seconds() const noexcept { return last_step_seconds_; }
  /// Wall-clock seconds spent in world steps since construction.
  double total_step_seconds() const noexcept { return total_step_seconds_; }
  /// Fixed updates handled since construction.
  std::uint64_t fixed_updates() const noexcept { return fixed_updates_; }

 private:
  granular::World& world_;
  int ticks_per_fixed_update_ = 1;
  double last_step_seconds_ = 0.0;
  double total_step_seconds_ = 0.0;
  std::uint64_t fixed_updates_ = 0;
};

}  // namespace engine
