#pragma once
/// @file timed_step.hpp
/// The one timing the benchmarks that step a World share.

#include <chrono>

#include "granular/world.hpp"

namespace granular::bench {

/// Seconds that `world.step(ticks)` takes (step synchronises with the device before returning).
inline double timed_step(World& world, int ticks) {
  const auto start = std::chrono::steady_clock::now();
  world.step(ticks);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace granular::bench
