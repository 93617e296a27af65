#include "session/screenshot_path.hpp"

#include <string>

namespace viewer {

std::filesystem::path next_screenshot_path(const std::filesystem::path& folder) {
  for (int n = 1;; ++n) {
    std::filesystem::path path = folder / ("granular-screenshot-" + std::to_string(n) + ".png");
    std::error_code error;
    if (!std::filesystem::exists(path, error)) return path;
  }
}

}  // namespace viewer
