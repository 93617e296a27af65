#pragma once
/// @file brick_detail.hpp
/// The level of detail marching cubes meshes each brick at, chosen from how large a cell appears on
/// the image: level 0 meshes a cube per cell; level 1 a cube per 2x2x2 cells, a quarter of the
/// triangles, where a cell covers less than a chosen number of pixels. A brick whose level changes
/// is rebuilt with its face neighbours (a coarse brick overlaps a finer neighbour: mc_build.comp).

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "granular/geometry.hpp"

namespace viewer {

/// Per-brick levels of detail for one grid of bricks.
class BrickDetail {
 public:
  /// A cube per cell.
  static constexpr std::uint8_t kFine = 0;
  /// A cube per 2x2x2 cells.
  static constexpr std::uint8_t kCoarse = 1;
  /// A coarse brick turns fine again only when its cells cover this many times `coarse_below`
  /// pixels, so a camera that stops near the threshold does not flip bricks back and forth.
  static constexpr float kHysteresis = 1.25f;

  /// Levels for `brick_counts` bricks: coarse where a cell covers fewer than `coarse_below`
  /// pixels of the image's height (0: every brick fine). Every brick starts fine.
  BrickDetail(granular::Int3 brick_counts, float coarse_below);

  /// Chooses every brick's level for a frame seen through `view_projection` (cells to clip space)
  /// on an image `image_height` pixels tall, judging each brick by its point nearest the eye.
  /// Appends to `rebuild` each brick whose level changed and its face neighbours; returns whether
  /// any level changed. An unchanged view changes nothing.
  bool update(const glm::mat4& view_projection, std::uint32_t image_height, std::vector<std::uint32_t>& rebuild);

  /// Every brick's level (granular/bricks.hpp numbering).
  std::span<const std::uint8_t> levels() const { return levels_; }

  /// Pixels of the image's height that a cell at clip-space depth `w` covers under
  /// `view_projection`, for an image `image_height` pixels tall.
  static float cell_pixels(const glm::mat4& view_projection, std::uint32_t image_height, float w);

 private:
  granular::Int3 counts_;
  float coarse_below_;
  std::vector<std::uint8_t> levels_;
  glm::mat4 last_view_{0.0f};
  std::uint32_t last_height_ = 0;
};

}  // namespace viewer
