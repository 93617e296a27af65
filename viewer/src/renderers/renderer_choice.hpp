#pragma once
/// @file renderer_choice.hpp
/// The sandbox's automatic renderer choice (`--renderer auto`, the default). The renderers differ
/// in cost by orders of magnitude, and in which is cheapest: on a GPU the ray march, then marching
/// cubes, then instanced cubes (bench/RESULTS.md); on a CPU rasteriser such as lavapipe the ray
/// march's cost grows with the pixels and the raster renderers' with the surface, so a settled
/// scene in a large window draws fastest as cubes. The choice measures each renderer in that order
/// (ray march, marching, cubes) and keeps the costliest that held the target frame rate, else the
/// fastest it measured.

#include <functional>
#include <optional>
#include <string>

#include "renderers/renderer.hpp"

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
  RendererKind first() const { return kOrder[0]; }

  /// True while the choice is still measuring.
  bool measuring() const { return !done_; }

  /// Adds a frame of `seconds` drawn by the current renderer. Returns the renderer to switch to
  /// when the current one's measurement is over and another is to be tried or kept.
  std::optional<RendererKind> frame(double seconds);

  /// Ends the trial of the renderer frame() asked for: it cannot be made on this device for this
  /// world (`why`), and counts as 0 FPS. Returns the renderer to switch to instead, as frame() does.
  std::optional<RendererKind> unavailable(const std::string& why);

  /// A frame as a sandbox runs it: frame(seconds), then `switch_to` each renderer it asks for until
  /// one can be made (switch_to throws VulkanError for one that cannot: unavailable()); each line
  /// to show goes to `print`. Returns the renderer drawing from now on when it changed.
  std::optional<RendererKind> advance(double seconds, const std::function<void(RendererKind)>& switch_to,
                                      const std::function<void(const std::string&)>& print);

  /// Ends the choice: the user picked a renderer.
  void stop() { done_ = true; }

  /// One line saying what was measured and chosen, after frame() switched or ended the choice.
  const std::string& report() const { return report_; }

 private:
  /// The renderers from the cheapest on a GPU to the costliest.
  static constexpr RendererKind kOrder[3] = {RendererKind::Raymarch, RendererKind::Marching, RendererKind::Cubes};
  int current_ = 0;          ///< index into kOrder
  bool first_frame_ = true;  ///< the current renderer's first frame (not measured)
  int frames_ = 0;           ///< measured frames of the current renderer
  double seconds_ = 0;       ///< their time
  double fps_[3] = {};       ///< frames per second measured per renderer of kOrder
  bool done_ = false;
  std::string report_;

  // Ends the current renderer's trial at `fps` (`note` in its line when it is not ""): the next
  // renderer to try, else the chosen one when it is not the current.
  std::optional<RendererKind> end_trial(double fps, const std::string& note);
};

}  // namespace viewer
