#include "renderer_choice.hpp"

#include <cstdio>

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
  const double fps = frames_ / seconds_;
  const bool holds = fps >= kTargetFps;
  const int last = int(std::size(kOrder)) - 1;
  char line[160];
  std::optional<RendererKind> next;
  if (holds && current_ < last) {
    next = kOrder[current_ + 1];
    std::snprintf(line, sizeof line, "renderer: %s (auto: %s %.1f FPS holds %.0f, trying the next)",
                  to_string(*next), to_string(kOrder[current_]), fps, kTargetFps);
    ++current_;
    first_frame_ = true;
    frames_ = 0;
    seconds_ = 0;
  } else {
    done_ = true;
    const int kept = holds || current_ == 0 ? current_ : current_ - 1;
    if (kept != current_) next = kOrder[kept];
    std::snprintf(line, sizeof line, "renderer: %s (auto: %s %.1f FPS, %s)", to_string(kOrder[kept]),
                  to_string(kOrder[current_]), fps,
                  holds ? "holds 60: chosen" : kept == current_ ? "below 60, the cheapest: chosen" : "below 60: the previous one chosen");
    current_ = kept;
  }
  report_ = line;
  return next;
}

}  // namespace viewer
