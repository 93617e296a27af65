#pragma once
/// @file screenshot_path.hpp
/// Where the sandbox's screenshot key writes: granular-screenshot-N.png in a folder, N the first
/// number from 1 whose file does not exist yet, so a later screenshot never overwrites an earlier one.

#include <filesystem>

namespace viewer {

/// `folder`/granular-screenshot-N.png for the smallest N >= 1 with no such file.
std::filesystem::path next_screenshot_path(const std::filesystem::path& folder);

}  // namespace viewer
