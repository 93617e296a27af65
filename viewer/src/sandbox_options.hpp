#pragma once
/// @file sandbox_options.hpp
/// The command line of granular-sandbox.

#include <optional>
#include <string>

#include "scene_loader.hpp"
#include "see_inside.hpp"

namespace CLI {
class App;
}

namespace viewer {

/// Everything the command line sets.
struct SandboxOptions {
  WorldChoice world;              ///< scene, size, backend, rules, threads
  bool headless = false;          ///< render offscreen with no window (no GLFW at all)
  std::optional<int> frames;      ///< --frames: frames to run (unset: headless_frames(), windowed until closed)
  std::string screenshot;         ///< PNG of the last frame
  std::string screenshot_dir = "."; ///< the folder the screenshot key (P) writes into
  SeeInside inside;               ///< --section and --xray: the section plane and x-ray at start
  std::string camera;             ///< "yaw,pitch,distance[,tx,ty,tz]" (empty: framing the content)
  std::string renderer = "auto";  ///< auto (renderer_choice.hpp), cubes, marching or raymarch
  int ticks_per_frame = 1;        ///< world ticks per engine fixed update (one fixed update per frame headless)
  int width = 1280;               ///< image width
  int height = 720;               ///< image height
  bool validation = false;        ///< Vulkan validation layers and a count of their messages
  bool no_interop = false;        ///< CUDA backend: upload through staging instead of sharing the cells
};

/// Frames a headless run renders when --frames is not given.
inline constexpr int kDefaultHeadlessFrames = 60;

/// Frames the headless run renders: --frames, else kDefaultHeadlessFrames.
inline int headless_frames(const SandboxOptions& options) { return options.frames.value_or(kDefaultHeadlessFrames); }

/// Registers the options on `app`; validation defaults on in debug builds.
void add_sandbox_options(CLI::App& app, SandboxOptions& options);

/// Throws std::invalid_argument naming the option when a value is out of range.
void validate(const SandboxOptions& options);

}  // namespace viewer
