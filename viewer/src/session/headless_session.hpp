#pragma once
/// @file headless_session.hpp
/// granular-sandbox --headless: the engine loop steps the world and renders offscreen frames with
/// no window and no GLFW; prints a summary and writes the last frame as a PNG.

#include "session/sandbox_options.hpp"

namespace viewer {

/// Runs the headless session; returns the process exit status (0 ok, 1 when validation reported
/// messages). Throws on bad input or a missing Vulkan device.
int run_headless(const SandboxOptions& options);

}  // namespace viewer
