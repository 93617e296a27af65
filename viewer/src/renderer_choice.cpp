#include "renderer_choice.hpp"

#include <cstdio>

#include "renderer_factory.hpp"

namespace viewer {

std::optional<RendererKind> RendererChoice::frame(double seconds) {
  if (done_) return std::nullopt;
  if (first_frame_) {
    first_frame_ = false;
    return std::nullopt;
  }
  ++frames_;
  seconds_ += seconds;
  if (frames_ < kTrialFrames || seconds_ < kTrialSeconds) return std::nullopt;
  fps_[current_] = frames_ / seconds_;
  char line[160];
  if (fps_[current_] >= kTargetFps || current_ == 2) {
    done_ = true;
    int best = current_;
    for (int i = 0; i <= current_; ++i)
      if (fps_[i] > fps_[best]) best = i;
    std::snprintf(line, sizeof line, "renderer: %s (auto: %s %.1f FPS%s)", to_string(order_[best]),
                  to_string(order_[current_]), fps_[current_],
                  fps_[current_] >= kTargetFps ? ", holds 60" : ", none held 60: the fastest measured");
    report_ = line;
    if (best == current_) return std::nullopt;
    current_ = best;
    return order_[best];
  }
  std::snprintf(line, sizeof line, "renderer: %s (auto: %s %.1f FPS, below 60)", to_string(order_[current_ + 1]),
                to_string(order_[current_]), fps_[current_]);
  report_ = line;
  ++current_;
  first_frame_ = true;
  frames_ = 0;
  seconds_ = 0;
  return order_[current_];
}

}  // namespace viewer
