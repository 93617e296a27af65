#include "engine/granular_subsystem.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

namespace engine {
namespace {

int checked_ticks(int ticks) {
  if (ticks < 1) {
    throw std::invalid_argument("GranularSubsystem: ticks_per_fixed_update must be >= 1 (got " +
                                std::to_string(ticks) + ")");
  }
  return ticks;
}

}  // namespace

GranularSubsystem::GranularSubsystem(granular::World& world, int ticks_per_fixed_update)
    : Subsystem("granular"),
      world_(world),
      ticks_per_fixed_update_(checked_ticks(ticks_per_fixed_update)) {}

void GranularSubsystem::set_ticks_per_fixed_update(int ticks) {
  ticks_per_fixed_update_ = checked_ticks(ticks);
}

void GranularSubsystem::fixed_update(double) {
  const auto start = std::chrono::steady_clock::now();
  world_.step(ticks_per_fixed_update_);
  last_step_seconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  total_step_seconds_ += last_step_seconds_;
  ++fixed_updates_;
}

}  // namespace engine
