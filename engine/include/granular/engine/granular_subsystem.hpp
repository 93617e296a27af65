#pragma once
/// @file granular_subsystem.hpp
/// Plugs a granular::World into the EngineLoop (target granular::engine_granular).

#include <cstdint>
#include <functional>

#include "granular/engine/subsystem.hpp"
#include "granular/world.hpp"

namespace granular::engine {

/// How a GranularSubsystem turns the loop's fixed updates into world ticks.
struct GranularSubsystemDef {
  /// World ticks per fixed update, whatever the update's length; 0 (the default) steps at the
  /// rules' real-time rate instead: each fixed update adds dt * time_scale to the time owed and
  /// runs the whole ticks of granular::tick_seconds(world.rules()) it holds. >= 0.
  int ticks_per_fixed_update = 0;
  /// Real-time rate: simulated seconds per second of loop time (1 = real time, 2 = twice as fast).
  /// Finite and > 0.
  double time_scale = 1.0;
  /// Real-time rate: the most world ticks one fixed update runs; time owed past them is dropped
  /// (counted in dropped_seconds()), so a world that steps slower than real time falls behind by a
  /// bounded amount instead of ever more. >= 1.
  int max_ticks_per_update = 8;
};

/// A Subsystem that steps a granular::World on every fixed update: by default at the rules'
/// real-time rate (one tick per granular::tick_seconds of loop time, 31.9 ms for the default rules,
/// whatever the loop's tick rate), or a fixed number of ticks per update. It can be paused and
/// single-stepped. The world is borrowed and must outlive this object.
class GranularSubsystem final : public Subsystem {
 public:
  /// Wraps `world` with `def` (validated: std::invalid_argument naming the field otherwise).
  explicit GranularSubsystem(granular::World& world, const GranularSubsystemDef& def = {});
  /// Wraps `world`, stepping it `ticks_per_fixed_update` (>= 1, std::invalid_argument otherwise)
  /// ticks per fixed update whatever dt is.
  GranularSubsystem(granular::World& world, int ticks_per_fixed_update);

  /// Steps the world the ticks this update owes (none while paused, except a requested step) and
  /// times the step with the steady clock.
  void fixed_update(double dt) override;

  /// The wrapped world.
  granular::World& world() noexcept { return world_; }
  /// The wrapped world.
  const granular::World& world() const noexcept { return world_; }
  /// The definition in use.
  const GranularSubsystemDef& def() const noexcept { return def_; }
  /// World ticks per fixed update; 0 when stepping at the real-time rate.
  int ticks_per_fixed_update() const noexcept { return def_.ticks_per_fixed_update; }
  /// Sets the world ticks per fixed update (0: the real-time rate; < 0 throws
  /// std::invalid_argument). The time owed is kept.
  void set_ticks_per_fixed_update(int ticks);
  /// Sets the real-time rate's time scale (finite and > 0, std::invalid_argument otherwise).
  void set_time_scale(double time_scale);
  /// The physical length of one world tick (granular::tick_seconds of the world's rules).
  double tick_seconds() const noexcept { return tick_seconds_; }

  /// What runs an update's ticks: given the number of ticks (>= 1), it must advance the world by
  /// exactly that many.
  using Stepper = std::function<void(int ticks)>;
  /// Runs the world's ticks through `stepper` from now on (a game that moves bodies by a physics
  /// engine steps both in lockstep, a tick at a time); an empty one restores World::step(ticks), the
  /// default. Throws std::logic_error when a stepper leaves the world at another tick than the
  /// ticks it was given.
  void set_stepper(Stepper stepper);

  /// Pauses (no ticks, no time owed) or resumes.
  void set_paused(bool paused) noexcept;
  /// True while paused.
  bool paused() const noexcept { return paused_; }
  /// While paused, makes the next fixed update run `ticks` (>= 1, std::invalid_argument
  /// otherwise) world ticks; requests add up.
  void request_step(int ticks = 1);

  /// World ticks the latest fixed update ran.
  int last_update_ticks() const noexcept { return last_update_ticks_; }
  /// Wall-clock seconds the latest world step took (0 before the first step).
  double last_step_seconds() const noexcept { return last_step_seconds_; }
  /// Wall-clock seconds spent in world steps since construction.
  double total_step_seconds() const noexcept { return total_step_seconds_; }
  /// Fixed updates handled since construction (paused ones included).
  std::uint64_t fixed_updates() const noexcept { return fixed_updates_; }
  /// Simulated seconds the world advanced through this subsystem: ticks run x tick_seconds().
  double simulated_seconds() const noexcept { return double(ticks_run_) * tick_seconds_; }
  /// Real-time rate: loop time dropped by max_ticks_per_update, scaled by time_scale.
  double dropped_seconds() const noexcept { return dropped_seconds_; }

 private:
  int ticks_owed(double dt);

  granular::World& world_;
  GranularSubsystemDef def_;
  Stepper stepper_;  ///< empty: World::step
  double tick_seconds_ = 0.0;
  double owed_seconds_ = 0.0;
  bool paused_ = false;
  int requested_ticks_ = 0;
  int last_update_ticks_ = 0;
  double last_step_seconds_ = 0.0;
  double total_step_seconds_ = 0.0;
  double dropped_seconds_ = 0.0;
  std::uint64_t fixed_updates_ = 0;
  std::uint64_t ticks_run_ = 0;
};

}  // namespace granular::engine
