#pragma once
/// @file pausable_subsystem.hpp
/// Wraps a subsystem so that its fixed updates can be paused and single-stepped from the UI.

#include "granular/engine/subsystem.hpp"

namespace viewer {

/// Forwards fixed_update to the wrapped subsystem unless paused; step() lets one through.
class PausableSubsystem final : public granular::engine::Subsystem {
 public:
  /// Wraps `inner` (which must outlive this).
  explicit PausableSubsystem(granular::engine::Subsystem& inner) : granular::engine::Subsystem("pausable"), inner_(inner) {}
  /// Runs the inner fixed update when running, or once per requested step when paused.
  void fixed_update(double dt) override {
    if (paused_ && steps_ == 0) return;
    if (paused_) --steps_;
    inner_.fixed_update(dt);
  }
  /// Pauses or resumes.
  void set_paused(bool paused) {
    paused_ = paused;
    steps_ = 0;
  }
  /// True while paused.
  bool paused() const { return paused_; }
  /// While paused, lets the next fixed update through.
  void step() { ++steps_; }

 private:
  granular::engine::Subsystem& inner_;
  bool paused_ = false;
  int steps_ = 0;
};

}  // namespace viewer
