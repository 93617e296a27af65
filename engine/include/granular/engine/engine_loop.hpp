#pragma once
/// @file engine_loop.hpp
/// The game loop: read the clock, run the fixed ticks the accumulator owes, then one variable
/// update and one render with the interpolation factor.

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "granular/engine/clock.hpp"
#include "granular/engine/fixed_timestep.hpp"
#include "granular/engine/subsystem.hpp"

namespace granular::engine {

/// What one EngineLoop::run_frame() did.
struct FrameStats {
  /// Index of this frame since the loop was created (the first frame is 0).
  std::uint64_t frame = 0;
  /// Clock time since the previous frame (0 for the first frame and when the clock went back).
  double measured_seconds = 0.0;
  /// Fixed ticks run (each calling fixed_update on every subsystem).
  int ticks = 0;
  /// The alpha passed to render(), in [0, 1).
  double alpha = 0.0;
  /// Seconds the spiral-of-death clamps dropped this frame.
  double dropped_seconds = 0.0;
  /// The frame time passed to update() (measured_seconds clamped to max_frame_seconds).
  double frame_seconds = 0.0;
};

/// Totals since the loop was created.
struct LoopStats {
  /// Frames run.
  std::uint64_t frames = 0;
  /// Fixed ticks run.
  std::uint64_t ticks = 0;
  /// Seconds dropped by the spiral-of-death clamps.
  double dropped_seconds = 0.0;
  /// Simulated time: the sum of the tick lengths of every tick run.
  double simulated_seconds = 0.0;
};

/// Drives subsystems at a fixed simulation rate and a variable frame rate. Single-threaded,
/// except request_stop(), which any thread may call.
class EngineLoop {
 public:
  /// Uses `clock` (which must outlive the loop) and a validated `config` (std::invalid_argument
  /// otherwise).
  explicit EngineLoop(Clock& clock, const FixedTimestepConfig& config = {});

  /// Appends `subsystem` (which must outlive the loop); subsystems are called in the order
  /// added. Throws std::invalid_argument when it was already added and std::logic_error when
  /// called from inside a frame.
  void add(Subsystem& subsystem);
  /// The subsystems in call order.
  std::span<Subsystem* const> subsystems() const noexcept { return subsystems_; }

  /// Runs one frame: reads the clock, advances the accumulator by the time since the previous
  /// frame (0 on the first), calls fixed_update(dt) `ticks` times on every subsystem in order
  /// (tick by tick: all subsystems for tick 1, then all for tick 2...), then update() on each,
  /// then render(alpha) on each. Exceptions from subsystems propagate; the frame is then not
  /// counted in stats().
  FrameStats run_frame();
  /// Runs frames while `keep_going()` (asked before each frame; an empty function means
  /// "always") is true and no stop is requested. Returns the number of frames run; a pending
  /// stop request is consumed.
  std::uint64_t run(const std::function<bool()>& keep_going);
  /// Runs `frames` (>= 0, std::invalid_argument otherwise) frames, fewer if a stop is
  /// requested. Returns the number of frames run; a pending stop request is consumed.
  int run_frames(int frames);
  /// Makes run() / run_frames() return after the current frame (or at once, if called before
  /// them). Safe to call from a subsystem or from another thread.
  void request_stop() noexcept { stop_requested_.store(true, std::memory_order_relaxed); }
  /// True while a stop is requested and not yet consumed by run() / run_frames().
  bool stop_requested() const noexcept { return stop_requested_.load(std::memory_order_relaxed); }

  /// Changes the timestep config (validated); the accumulated time carries over.
  void set_config(const FixedTimestepConfig& config) { timestep_.set_config(config); }
  /// Changes only the tick rate (validated as in set_config).
  void set_tick_rate_hz(double tick_rate_hz);
  /// The timestep config in use.
  const FixedTimestepConfig& config() const noexcept { return timestep_.config(); }
  /// The accumulator (tick length, time owed).
  const FixedTimestep& timestep() const noexcept { return timestep_; }
  /// Totals since creation.
  const LoopStats& stats() const noexcept { return stats_; }
  /// The stats of the latest completed frame (all zero before the first).
  const FrameStats& last_frame() const noexcept { return last_frame_; }

 private:
  Clock& clock_;
  FixedTimestep timestep_;
  std::vector<Subsystem*> subsystems_;
  LoopStats stats_;
  FrameStats last_frame_;
  double last_time_ = 0.0;
  bool started_ = false;
  bool in_frame_ = false;
  std::atomic<bool> stop_requested_{false};
};

}  // namespace granular::engine
