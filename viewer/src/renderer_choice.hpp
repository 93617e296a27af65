#pragma once
/// @file renderer_choice.hpp
/// The sandbox's automatic renderer choice (`--renderer auto`, the default): it tries the renderers
/// from the richest look to the fastest (instanced cubes, marching cubes, ray march; the order of
/// their measured cost, bench/RESULTS.md) and keeps the first that holds the target frame rate on
/// the device and scene it finds, else the fastest it measured.

#include <optional>
#include <string>

#include "renderer.hpp"

namespace viewer {

/// Frames per second the automatic choice asks a renderer to hold.
inline constexpr double kTargetFps = 60.0;

/// Picks a renderer by measuring frames (see the file comment). Each renderer is given
/// kTrialSeconds of frames after its first one (which rebuilds every brick and may compile its
/// pipelines), and at least kTrialFrames of them.
class RendererChoice {
 public:
  /// Seconds of frames a renderer is measured over.
  static constexpr double kTrialSeconds = 0.5;
  /// Frames a renderer is measured over at least.
  static constexpr int kTrialFrames = 3;

  /// The renderer to start with.
  RendererKind first() const { return order_[0]; }

  /// True while the choice is still measuring.
  bool measuring() const { return !done_; }

  /// Adds a frame of `seconds` drawn by the current renderer. Returns the renderer to switch to
  /// when the measurement of the current one is over and another is to be tried or kept.
  std::optional<RendererKind> frame(double seconds);

  /// Ends the choice: the user picked a renderer.
  void stop() { done_ = true; }

  /// One line saying what was measured and chosen (after frame() returned a switch or ended).
  const std::string& report() const { return report_; }

 private:
  static constexpr RendererKind order_[3] = {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch};
  int current_ = 0;          ///< index into order_
  bool first_frame_ = true;  ///< the current renderer's first frame (not measured)
  int frames_ = 0;           ///< measured frames of the current renderer
  double seconds_ = 0;       ///< their time
  double fps_[3] = {};       ///< measured frames per second per renderer (0: not measured)
  bool done_ = false;
  std::string report_;
};

}  // namespace viewer
