#pragma once
/// @file sandbox_options.hpp
/// The command line of granular-sandbox.

#include <optional>
#include <string>

#include "session/scene_loader.hpp"
#include "renderers/renderer.hpp"
#include "section/see_inside.hpp"

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
  RenderDetail detail;            ///< --coarse-below: where marching cubes meshes bricks at half resolution
  int ticks_per_frame = 1;        ///< world ticks per engine fixed update (one fixed update per frame headless)
  int width = 1280;               ///< image width
  int height = 720;               ///< image height
  bool validation = false;        ///< Vulkan validation layers and a count of their messages
  bool no_interop = false;        ///< CUDA backend: upload through staging instead of sharing the cells
  std::string save;               ///< --save: snapshot written after the last frame, and Ctrl+S/Ctrl+O's file
  std::string load;               ///< --load: the snapshot to start from ("" for none)
  bool scene_given = false;       ///< --scene was on the command line
  int undo_mib = 256;             ///< the undo history's bound in MiB
};

/// Largest --ticks-per-frame. A frame at 60 FPS has 16.7 ms; real time is about 4 ticks a frame
/// (250 ticks a second for one step per tick), so 1000 is 250 times real time, and a moving tick of
/// even the smallest scene costs a few microseconds (3 to 12 us for `pile` at N=24 on the CPU), so
/// 1000 ticks take a frame or more. 2^31 - 1 ticks would hold one frame for hours.
inline constexpr int kMaxTicksPerFrame = 1000;

/// Frames a headless run renders when --frames is not given.
inline constexpr int kDefaultHeadlessFrames = 60;

/// Frames the headless run renders: --frames, else kDefaultHeadlessFrames.
inline int headless_frames(const SandboxOptions& options) { return options.frames.value_or(kDefaultHeadlessFrames); }

/// Registers the options on `app`; validation defaults on in debug builds.
void add_sandbox_options(CLI::App& app, SandboxOptions& options);

/// Throws std::invalid_argument naming the option when a value is out of range (--ticks-per-frame
/// 1..kMaxTicksPerFrame, an empty --save, --load or --screenshot) or two options conflict, and granular::Error when --save names a path a snapshot cannot be saved at (before
/// any frame).
void validate(const SandboxOptions& options);

/// The world the sandbox starts from: --load's snapshot when given, else --scene and --size.
WorldChoice start_choice(const SandboxOptions& options);

/// The snapshot file of Ctrl+S and Ctrl+O: --save, else kDefaultSnapshotFile.
std::string snapshot_file(const SandboxOptions& options);

}  // namespace viewer
