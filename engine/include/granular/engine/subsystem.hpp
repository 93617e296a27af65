#pragma once
/// @file subsystem.hpp
/// The unit of work the engine loop drives: physics, audio, a renderer, a voxel world...

#include <string>
#include <string_view>
#include <utility>

namespace granular::engine {

/// One part of a game that the EngineLoop calls every frame. Override what you need; the
/// default hooks do nothing. Not copyable (the loop keeps references to subsystems).
class Subsystem {
 public:
  /// Destroys the subsystem.
  virtual ~Subsystem() = default;
  /// Not copyable: the loop holds subsystems by reference.
  Subsystem(const Subsystem&) = delete;
  /// Not copyable: the loop holds subsystems by reference.
  Subsystem& operator=(const Subsystem&) = delete;

  /// Advances the simulation by one fixed tick of `dt` seconds; called 0..max_ticks_per_frame
  /// times a frame, always with the same dt until the tick rate changes.
  virtual void fixed_update(double dt);
  /// Per-frame work at the variable frame rate (input, camera, UI); `frame_seconds` is the
  /// frame time after the max_frame_seconds clamp. Called once a frame, after the fixed ticks.
  virtual void update(double frame_seconds);
  /// Draws (or hands over for drawing) the state interpolated `alpha` in [0, 1) of the way from
  /// the previous fixed tick to the latest one. Called once a frame, after update().
  virtual void render(double alpha);

  /// The name given at construction, for logs and profilers.
  std::string_view name() const noexcept { return name_; }

 protected:
  /// Names the subsystem.
  explicit Subsystem(std::string name) : name_(std::move(name)) {}

 private:
  std::string name_;
};

}  // namespace granular::engine
