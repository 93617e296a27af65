#include "granular/engine/granular_subsystem.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "granular/time_scale.hpp"

namespace granular::engine {
namespace {

const GranularSubsystemDef& checked(const GranularSubsystemDef& def) {
  if (def.ticks_per_fixed_update < 0)
    throw std::invalid_argument("GranularSubsystemDef::ticks_per_fixed_update = " +
                                std::to_string(def.ticks_per_fixed_update) + "; use 0 (real-time rate) or >= 1");
  if (!std::isfinite(def.time_scale) || def.time_scale <= 0)
    throw std::invalid_argument("GranularSubsystemDef::time_scale = " + std::to_string(def.time_scale) +
                                " must be finite and > 0");
  if (def.max_ticks_per_update < 1)
    throw std::invalid_argument("GranularSubsystemDef::max_ticks_per_update = " +
                                std::to_string(def.max_ticks_per_update) + " must be >= 1");
  return def;
}

GranularSubsystemDef fixed_ticks(int ticks) {
  if (ticks < 1)
    throw std::invalid_argument("GranularSubsystem: ticks_per_fixed_update must be >= 1 (got " + std::to_string(ticks) +
                                ")");
  GranularSubsystemDef def;
  def.ticks_per_fixed_update = ticks;
  return def;
}

}  // namespace

GranularSubsystem::GranularSubsystem(granular::World& world, const GranularSubsystemDef& def)
    : Subsystem("granular"), world_(world), def_(checked(def)), tick_seconds_(granular::tick_seconds(world.rules())) {}

GranularSubsystem::GranularSubsystem(granular::World& world, int ticks_per_fixed_update)
    : GranularSubsystem(world, fixed_ticks(ticks_per_fixed_update)) {}

void GranularSubsystem::set_ticks_per_fixed_update(int ticks) {
  GranularSubsystemDef def = def_;
  def.ticks_per_fixed_update = ticks;
  def_ = checked(def);
}

void GranularSubsystem::set_time_scale(double time_scale) {
  GranularSubsystemDef def = def_;
  def.time_scale = time_scale;
  def_ = checked(def);
}

void GranularSubsystem::set_stepper(Stepper stepper) { stepper_ = std::move(stepper); }

void GranularSubsystem::set_paused(bool paused) noexcept {
  paused_ = paused;
  requested_ticks_ = 0;
}

void GranularSubsystem::request_step(int ticks) {
  if (ticks < 1)
    throw std::invalid_argument("GranularSubsystem::request_step: ticks = " + std::to_string(ticks) + " must be >= 1");
  requested_ticks_ += ticks;
}

int GranularSubsystem::ticks_owed(double dt) {
  if (paused_) {
    const int ticks = requested_ticks_;
    requested_ticks_ = 0;
    return ticks;
  }
  if (def_.ticks_per_fixed_update > 0) return def_.ticks_per_fixed_update;
  owed_seconds_ += dt * def_.time_scale;
  const double whole = std::floor(owed_seconds_ / tick_seconds_);
  if (whole <= def_.max_ticks_per_update) {
    owed_seconds_ -= whole * tick_seconds_;
    return int(whole);
  }
  const double kept = owed_seconds_ - whole * tick_seconds_;
  dropped_seconds_ += owed_seconds_ - kept - def_.max_ticks_per_update * tick_seconds_;
  owed_seconds_ = kept;
  return def_.max_ticks_per_update;
}

void GranularSubsystem::fixed_update(double dt) {
  ++fixed_updates_;
  last_update_ticks_ = ticks_owed(dt);
  if (last_update_ticks_ == 0) return;
  const auto start = std::chrono::steady_clock::now();
  if (stepper_) {
    const std::uint64_t before = world_.tick();
    stepper_(last_update_ticks_);
    if (world_.tick() != before + std::uint64_t(last_update_ticks_))
      throw std::logic_error("GranularSubsystem: the stepper ran the world from tick " + std::to_string(before) +
                             " to " + std::to_string(world_.tick()) + ", not " +
                             std::to_string(last_update_ticks_) + " ticks");
  } else {
    world_.step(last_update_ticks_);
  }
  last_step_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  total_step_seconds_ += last_step_seconds_;
  ticks_run_ += std::uint64_t(last_update_ticks_);
}

}  // namespace granular::engine
