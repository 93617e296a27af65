#pragma once
/// @file clock.hpp
/// Time sources for the engine loop: the real monotonic clock and a hand-driven fake for tests.

#include <chrono>

namespace granular::engine {

/// A source of monotonic time, in seconds. The loop only ever subtracts two readings, so the
/// epoch is arbitrary.
class Clock {
 public:
  /// Destroys the clock.
  virtual ~Clock() = default;
  /// The current time in seconds since the clock's epoch.
  virtual double now_seconds() = 0;
};

/// The real clock: std::chrono::steady_clock, counted from the moment this object was created
/// (so the double keeps sub-microsecond precision for years of uptime).
class SteadyClock final : public Clock {
 public:
  /// Starts the clock at 0 now.
  SteadyClock();
  /// Seconds since construction.
  double now_seconds() override;

 private:
  std::chrono::steady_clock::time_point epoch_;
};

/// A fake clock that only moves when told to; tests use it to feed the loop exact frame times.
class ManualClock final : public Clock {
 public:
  /// Starts the clock at `start_seconds`.
  explicit ManualClock(double start_seconds = 0.0) noexcept : now_(start_seconds) {}
  /// The time last set.
  double now_seconds() override { return now_; }
  /// Sets the time to `seconds` (it may move backwards; the loop treats that as a zero delta).
  void set(double seconds) noexcept { now_ = seconds; }
  /// Moves the time forward by `seconds`.
  void advance(double seconds) noexcept { now_ += seconds; }

 private:
  double now_;
};

}  // namespace granular::engine
