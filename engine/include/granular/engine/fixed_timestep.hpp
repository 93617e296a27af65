#pragma once
/// @file fixed_timestep.hpp
/// The fixed-timestep accumulator of Gaffer's "Fix Your Timestep!": variable frame times in,
/// a whole number of fixed ticks and an interpolation factor out, with a spiral-of-death clamp.

namespace granular::engine {

/// Parameters of a FixedTimestep. Every field has a usable default.
struct FixedTimestepConfig {
  /// Fixed ticks per second of simulated time (finite, > 0); one tick lasts 1 / tick_rate_hz s.
  double tick_rate_hz = 60.0;
  /// Most ticks one frame may run (>= 1); whole ticks beyond it are dropped, not queued.
  int max_ticks_per_frame = 8;
  /// Longest frame time accepted (> 0, +infinity disables the clamp); the rest is dropped.
  double max_frame_seconds = 0.25;
};

/// Throws std::invalid_argument naming the offending field and its value when `config` is
/// unusable: tick_rate_hz not finite or <= 0, max_ticks_per_frame < 1, max_frame_seconds NaN
/// or <= 0.
void validate(const FixedTimestepConfig& config);

/// What one call of FixedTimestep::advance() decided.
struct FrameTicks {
  /// Fixed ticks to run this frame, in [0, max_ticks_per_frame].
  int ticks = 0;
  /// Interpolation factor in [0, 1) for rendering between the last two simulated states: the
  /// time left in the accumulator after the ticks were taken, divided by the tick length.
  double alpha = 0.0;
  /// Seconds discarded this frame by the two clamps (frame over max_frame_seconds, ticks over
  /// max_ticks_per_frame); 0 on an ordinary frame.
  double dropped_seconds = 0.0;
  /// The frame time actually added to the accumulator (the input clamped to max_frame_seconds).
  double frame_seconds = 0.0;
};

/// Turns variable frame times into whole fixed ticks. For every frame,
/// `input = ticks * tick_seconds() + dropped_seconds + (accumulator after - accumulator before)`.
class FixedTimestep {
 public:
  /// Starts with an empty accumulator. Throws std::invalid_argument for an invalid config.
  explicit FixedTimestep(const FixedTimestepConfig& config = {});

  /// Adds a frame of `frame_seconds` (finite, >= 0; std::invalid_argument otherwise) and returns
  /// the ticks to run. A frame longer than max_frame_seconds is cut to it and the excess dropped;
  /// whole ticks beyond max_ticks_per_frame are dropped too, while the fraction of a tick left
  /// over stays in the accumulator and gives alpha. Ticks owed within a billionth of a tick are
  /// run, so that frames summing to one tick in floating point (10 x 1/600 s at 60 Hz) give one.
  FrameTicks advance(double frame_seconds);

  /// Replaces the config (validated as in the constructor). The time in the accumulator is
  /// kept, in seconds, and is spent in ticks of the new length from the next advance() on.
  void set_config(const FixedTimestepConfig& config);
  /// The current config.
  const FixedTimestepConfig& config() const noexcept { return config_; }
  /// Length of one fixed tick in seconds (1 / tick_rate_hz).
  double tick_seconds() const noexcept { return tick_seconds_; }
  /// Seconds owed to the simulation but not yet run as ticks.
  double accumulator_seconds() const noexcept { return accumulator_; }
  /// Empties the accumulator (after a pause or a level load, say).
  void reset() noexcept { accumulator_ = 0.0; }

 private:
  FixedTimestepConfig config_;
  double tick_seconds_ = 0.0;
  double accumulator_ = 0.0;
};

}  // namespace granular::engine
