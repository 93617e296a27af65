#pragma once
/// @file sandbox_app.hpp
/// The windowed sandbox: GLFW window, swapchain, mouse and keyboard tools, Dear ImGui HUD.

#include "session/sandbox_options.hpp"

namespace viewer {

/// Opens the window and runs until it is closed (or options.frames frames when > 0); returns the
/// exit status. Throws when there is no display or no Vulkan device that can present.
int run_windowed(const SandboxOptions& options);

}  // namespace viewer
