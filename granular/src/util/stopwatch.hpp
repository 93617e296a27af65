#pragma once
/// @file stopwatch.hpp
/// Host wall time, lap by lap: StepProfile's phases and a DistributedWorld's halo exchange.

#include <chrono>

namespace granular {

/// Times the phases of a call one after another on the host's steady clock.
class Stopwatch {
 public:
  /// Milliseconds since the last lap() (or since it was made), starting the next lap.
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace granular
