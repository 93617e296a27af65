#include "session/sandbox_options.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "granular/rule_presets.hpp"
#include "granular/world_snapshot.hpp"
#include "renderers/renderer_factory.hpp"
#include "session/world_files.hpp"

namespace viewer {

namespace {

/// A CLI11 check that refuses an empty file name, which would otherwise mean "none" silently.
CLI::Validator non_empty_file() {
  return CLI::Validator(
      [](std::string& value) { return value.empty() ? std::string("needs a file name; an empty value names none") : std::string(); },
      "FILE", "non-empty file name");
}

}  // namespace

void add_sandbox_options(CLI::App& app, SandboxOptions& o) {
#ifndef NDEBUG
  o.validation = true;
#endif
  app.add_option("--scene", o.world.scene,
                 "scene name from assets/scenes, a scene .json, a .raw/.vox grid, or a .gsnap snapshot")
      ->each([&o](const std::string&) { o.scene_given = true; });
  app.add_option_function<int>(
      "--size",
      [&o](const int& n) {
        if (n < 1)
          throw std::invalid_argument("--size " + std::to_string(n) +
                                      ": must be at least 1 (omit --size for the scene's default N)");
        o.world.size = n;
      },
      "scene size parameter N (default: the scene's own)");
  app.add_option("--backend", o.world.backend, "auto, cpu or cuda");
  std::string presets;
  for (const auto& name : granular::rule_preset_names()) presets += (presets.empty() ? "" : ", ") + name;
  app.add_option("--rules", o.world.rules, "rule-set preset (" + presets + "); a snapshot keeps its own")
      ->each([&o](const std::string&) { o.world.rules_given = true; });
  app.add_option("--threads", o.world.threads, "CPU backend threads (0: all)");
  app.add_flag("--headless", o.headless, "render offscreen, no window, no display needed");
  app.add_option_function<int>("--frames", [&o](const int& n) { o.frames = n; },
                               "frames to run (headless: default " + std::to_string(kDefaultHeadlessFrames) +
                                   "; windowed: default until the window is closed or Esc)");
  app.add_option("--screenshot", o.screenshot, "write the last frame to this PNG (windowed: the frame before it closes)")
      ->check(non_empty_file());
  app.add_option("--screenshot-dir", o.screenshot_dir,
                 "folder the P key writes granular-screenshot-N.png into (default: the current folder)");
  app.add_option_function<std::string>(
      "--section", [&o](const std::string& text) { o.inside.section = parse_section(text); },
      "AXIS:FRACTION: a section plane across axis x, y or z at FRACTION (0..1) of the grid, removing the half "
      "between the camera and the plane (keys V, comma, period)");
  app.add_flag("--xray", o.inside.xray, "draw static materials translucent (key B)");
  app.add_option("--camera", o.camera,
                 "yaw,pitch,distance[,tx,ty,tz]: degrees, distance and target as fractions of the grid "
                 "(default: framing the scene's non-void cells)");
  app.add_option("--renderer", o.renderer,
                 "auto (the default: measures the ray march, marching cubes and cubes here and keeps the "
                 "costliest holding 60 FPS, else the fastest), cubes, marching or raymarch");
  app.add_option("--coarse-below", o.detail.coarse_below_pixels,
                 "marching cubes meshes a brick with a cube per 2x2x2 cells where its cells cover fewer pixels "
                 "than this (default 1; 0: a cube per cell everywhere)")
      ->check(CLI::Range(0.0f, 1000.0f));
  app.add_option("--ticks-per-frame", o.ticks_per_frame,
                 "world ticks per fixed update (1.." + std::to_string(kMaxTicksPerFrame) + ")");
  app.add_option("--width", o.width, "image width in pixels");
  app.add_option("--height", o.height, "image height in pixels");
  app.add_flag("--validation,!--no-validation", o.validation, "Vulkan validation layers (default on in debug builds)");
  app.add_flag("--no-interop", o.no_interop, "with --backend cuda: copy the cells through the host instead of sharing them");
  app.add_option("--save", o.save,
                 std::string("snapshot (.gsnap) written after the last frame, and the file of Ctrl+S and Ctrl+O (default ") +
                     kDefaultSnapshotFile + ", written only by Ctrl+S)")
      ->check(non_empty_file());
  app.add_option("--load", o.load, "start from this snapshot (.gsnap), as saved by --save or Ctrl+S")->check(non_empty_file());
  app.add_option("--undo-mib", o.undo_mib, "memory for the undo history of strokes, in MiB (oldest strokes dropped first)");
}

void validate(const SandboxOptions& o) {
  if (o.frames && *o.frames < 1) throw std::invalid_argument("--frames must be >= 1, got " + std::to_string(*o.frames));
  if (o.ticks_per_frame < 1 || o.ticks_per_frame > kMaxTicksPerFrame)
    throw std::invalid_argument("--ticks-per-frame " + std::to_string(o.ticks_per_frame) + ": must be 1.." +
                                std::to_string(kMaxTicksPerFrame) + " (more ticks than a frame can run freeze the window)");
  if (o.width < 16 || o.height < 16 || o.width > 16384 || o.height > 16384)
    throw std::invalid_argument("--width/--height must be in 16..16384, got " + std::to_string(o.width) + "x" + std::to_string(o.height));
  // CLI::Range lets NaN through (every comparison with it is false).
  if (!(o.detail.coarse_below_pixels >= 0.0f && o.detail.coarse_below_pixels <= 1000.0f))
    throw std::invalid_argument("--coarse-below " + std::to_string(o.detail.coarse_below_pixels) + ": must be 0..1000");
  if (o.renderer != "auto" && !parse_renderer_kind(o.renderer))
    throw std::invalid_argument("--renderer '" + o.renderer + "': expected auto, cubes, marching or raymarch");
  std::error_code error;
  if (!std::filesystem::is_directory(o.screenshot_dir, error))
    throw std::invalid_argument("--screenshot-dir '" + o.screenshot_dir + "': not a folder");
  if (o.undo_mib < 1 || o.undo_mib > 1 << 20)
    throw std::invalid_argument("--undo-mib must be in 1..1048576, got " + std::to_string(o.undo_mib));
  if (!o.load.empty() && o.scene_given)
    throw std::invalid_argument("--load " + o.load + " and --scene " + o.world.scene + " both name the world to start from; give one");
  if (!o.load.empty() && !granular::is_snapshot_file(o.load))
    throw std::invalid_argument("--load " + o.load + ": expected a snapshot file (.gsnap); --scene takes scenes and .raw/.vox grids");
  if (!o.save.empty()) granular::check_snapshot_save_path(o.save);
}

WorldChoice start_choice(const SandboxOptions& o) {
  WorldChoice choice = o.world;
  if (!o.load.empty()) choice.scene = o.load;
  return choice;
}

std::string snapshot_file(const SandboxOptions& o) { return o.save.empty() ? kDefaultSnapshotFile : o.save; }

}  // namespace viewer
