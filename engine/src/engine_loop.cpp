#include "granular/engine/engine_loop.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace granular::engine {
namespace {

/// Clears a flag when the scope ends, exceptions included.
class FlagGuard {
 public:
  explicit FlagGuard(bool& flag) noexcept : flag_(flag) { flag_ = true; }
  ~FlagGuard() { flag_ = false; }
  FlagGuard(const FlagGuard&) = delete;
  FlagGuard& operator=(const FlagGuard&) = delete;

 private:
  bool& flag_;
};

}  // namespace

EngineLoop::EngineLoop(Clock& clock, const FixedTimestepConfig& config)
    : clock_(clock), timestep_(config) {}

void EngineLoop::add(Subsystem& subsystem) {
  if (in_frame_) {
    throw std::logic_error("EngineLoop::add: cannot add subsystem '" +
                           std::string(subsystem.name()) + "' from inside a frame");
  }
  if (std::find(subsystems_.begin(), subsystems_.end(), &subsystem) != subsystems_.end()) {
    throw std::invalid_argument("EngineLoop::add: subsystem '" + std::string(subsystem.name()) +
                                "' was already added");
  }
  subsystems_.push_back(&subsystem);
}

void EngineLoop::set_tick_rate_hz(double tick_rate_hz) {
  FixedTimestepConfig config = timestep_.config();
  config.tick_rate_hz = tick_rate_hz;
  timestep_.set_config(config);
}

FrameStats EngineLoop::run_frame() {
  if (in_frame_) {
    throw std::logic_error("EngineLoop::run_frame: called from inside a frame");
  }
  FlagGuard guard(in_frame_);

  const double now = clock_.now_seconds();
  FrameStats frame;
  frame.frame = stats_.frames;
  if (started_ && now > last_time_) {
    frame.measured_seconds = now - last_time_;
  }
  last_time_ = now;
  started_ = true;

  const FrameTicks ticks = timestep_.advance(frame.measured_seconds);
  frame.ticks = ticks.ticks;
  frame.alpha = ticks.alpha;
  frame.dropped_seconds = ticks.dropped_seconds;
  frame.frame_seconds = ticks.frame_seconds;

  const double dt = timestep_.tick_seconds();
  for (int tick = 0; tick < ticks.ticks; ++tick) {
    for (Subsystem* subsystem : subsystems_) {
      subsystem->fixed_update(dt);
    }
  }
  for (Subsystem* subsystem : subsystems_) {
    subsystem->update(ticks.frame_seconds);
  }
  for (Subsystem* subsystem : subsystems_) {
    subsystem->render(ticks.alpha);
  }

  stats_.frames += 1;
  stats_.ticks += static_cast<std::uint64_t>(ticks.ticks);
  stats_.dropped_seconds += ticks.dropped_seconds;
  stats_.simulated_seconds += ticks.ticks * dt;
  last_frame_ = frame;
  return frame;
}

std::uint64_t EngineLoop::run(const std::function<bool()>& keep_going) {
  std::uint64_t frames = 0;
  while (!stop_requested() && (!keep_going || keep_going())) {
    run_frame();
    ++frames;
  }
  stop_requested_.store(false, std::memory_order_relaxed);
  return frames;
}

int EngineLoop::run_frames(int frames) {
  if (frames < 0) {
    throw std::invalid_argument("EngineLoop::run_frames: frames must be >= 0 (got " +
                                std::to_string(frames) + ")");
  }
  int done = 0;
  while (done < frames && !stop_requested()) {
    run_frame();
    ++done;
  }
  stop_requested_.store(false, std::memory_order_relaxed);
  return done;
}

}  // namespace granular::engine
