#include "granular/engine/fixed_timestep.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace granular::engine {
namespace {

/// Ticks owed within this fraction of a tick count as owed (absorbs floating-point sums).
constexpr double kTickTolerance = 1e-9;

template <typename T>
[[noreturn]] void throw_invalid(const char* what, T value, const char* rule) {
  std::ostringstream message;
  message << what << " must be " << rule << " (got " << value << ")";
  throw std::invalid_argument(message.str());
}

}  // namespace

void validate(const FixedTimestepConfig& config) {
  if (!std::isfinite(config.tick_rate_hz) || !(config.tick_rate_hz > 0.0)) {
    throw_invalid("FixedTimestepConfig::tick_rate_hz", config.tick_rate_hz, "finite and > 0");
  }
  if (config.max_ticks_per_frame < 1) {
    throw_invalid("FixedTimestepConfig::max_ticks_per_frame", config.max_ticks_per_frame, ">= 1");
  }
  if (!(config.max_frame_seconds > 0.0)) {
    throw_invalid("FixedTimestepConfig::max_frame_seconds", config.max_frame_seconds, "> 0");
  }
}

FixedTimestep::FixedTimestep(const FixedTimestepConfig& config) { set_config(config); }

void FixedTimestep::set_config(const FixedTimestepConfig& config) {
  validate(config);
  config_ = config;
  tick_seconds_ = 1.0 / config.tick_rate_hz;
}

FrameTicks FixedTimestep::advance(double frame_seconds) {
  if (!std::isfinite(frame_seconds) || frame_seconds < 0.0) {
    throw_invalid("FixedTimestep::advance frame_seconds", frame_seconds, "finite and >= 0");
  }
  FrameTicks result;
  result.frame_seconds = frame_seconds;
  if (frame_seconds > config_.max_frame_seconds) {
    result.dropped_seconds = frame_seconds - config_.max_frame_seconds;
    result.frame_seconds = config_.max_frame_seconds;
  }
  accumulator_ += result.frame_seconds;

  const double owed = std::floor(accumulator_ / tick_seconds_ + kTickTolerance);
  const double max_ticks = static_cast<double>(config_.max_ticks_per_frame);
  const double run = owed > max_ticks ? max_ticks : owed;
  result.ticks = static_cast<int>(run);
  result.dropped_seconds += (owed - run) * tick_seconds_;

  accumulator_ -= owed * tick_seconds_;
  if (accumulator_ < 0.0) {
    accumulator_ = 0.0;
  }
  if (accumulator_ >= tick_seconds_) {
    // Only reachable through rounding when the accumulator is huge next to a tick.
    result.dropped_seconds += accumulator_;
    accumulator_ = 0.0;
  }
  result.alpha = accumulator_ / tick_seconds_;
  if (result.alpha >= 1.0) {
    result.alpha = std::nextafter(1.0, 0.0);
  }
  return result;
}

}  // namespace granular::engine
