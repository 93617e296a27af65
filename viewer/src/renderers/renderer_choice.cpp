#include "renderers/renderer_choice.hpp"

#include <cstdio>

#include "vulkan/vulkan_check.hpp"

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
  return end_trial(frames_ / seconds_, "");
}

std::optional<RendererKind> RendererChoice::unavailable(const std::string& why) {
  if (done_) return std::nullopt;
  return end_trial(0.0, "unavailable here: " + why);
}

std::optional<RendererKind> RendererChoice::end_trial(double fps, const std::string& note) {
  fps_[current_] = fps;
  char measured[300];
  if (note.empty())
    std::snprintf(measured, sizeof measured, "%s %.1f FPS", to_string(kOrder[current_]), fps);
  else
    std::snprintf(measured, sizeof measured, "%s %s", to_string(kOrder[current_]), note.c_str());
  const int last = int(std::size(kOrder)) - 1;
  char line[400];
  if (current_ < last) {
    std::snprintf(line, sizeof line, "renderer: %s (auto: %s, measuring the next)", to_string(kOrder[current_ + 1]),
                  measured);
    report_ = line;
    ++current_;
    first_frame_ = true;
    frames_ = 0;
    seconds_ = 0;
    return kOrder[current_];
  }
  done_ = true;
  int kept = -1;
  for (int i = 0; i <= last; ++i)
    if (fps_[i] >= kTargetFps) kept = i;  // the costliest that held it
  const bool held = kept >= 0;
  if (!held) {
    kept = 0;
    for (int i = 1; i <= last; ++i)
      if (fps_[i] > fps_[kept]) kept = i;
  }
  std::snprintf(line, sizeof line, "renderer: %s (auto: raymarch %.1f, marching %.1f, cubes %.1f FPS; %s: chosen)",
                to_string(kOrder[kept]), fps_[0], fps_[1], fps_[2],
                held ? "the costliest holding 60" : "none held 60, the fastest");
  report_ = line;
  const int measured_last = current_;
  current_ = kept;
  return kept == measured_last ? std::nullopt : std::optional<RendererKind>(kOrder[kept]);
}

std::optional<RendererKind> RendererChoice::advance(double seconds, const std::function<void(RendererKind)>& switch_to,
                                                    const std::function<void(const std::string&)>& print) {
  if (done_) return std::nullopt;
  std::optional<RendererKind> next = frame(seconds);
  std::optional<RendererKind> now;
  while (next) {
    try {
      switch_to(*next);
      now = next;
      break;
    } catch (const VulkanError& e) {
      print(report_);
      next = unavailable(e.what());
    }
  }
  if (now || !measuring()) print(report_);
  return now;
}

}  // namespace viewer
