#include "cells/brick_detail.hpp"

#include <cmath>

#include "granular/bricks.hpp"

namespace viewer {

BrickDetail::BrickDetail(granular::Int3 brick_counts, float coarse_below)
    : counts_(brick_counts),
      coarse_below_(coarse_below),
      levels_(std::size_t(brick_counts.x) * brick_counts.y * brick_counts.z, kFine) {}

float BrickDetail::cell_pixels(const glm::mat4& view_projection, std::uint32_t image_height, float w) {
  // Clip-space y per cell at w = 1: the length of the matrix's y row (the view's rows are unit).
  const float y_scale = glm::length(glm::vec3(view_projection[0][1], view_projection[1][1], view_projection[2][1]));
  return 0.5f * float(image_height) * y_scale / w;
}

bool BrickDetail::update(const glm::mat4& view_projection, std::uint32_t image_height,
                         std::vector<std::uint32_t>& rebuild) {
  if (coarse_below_ <= 0.0f || (view_projection == last_view_ && image_height == last_height_)) return false;
  last_view_ = view_projection;
  last_height_ = image_height;
  const glm::vec4 depth_row(view_projection[0][3], view_projection[1][3], view_projection[2][3], view_projection[3][3]);
  const float brick_radius = 0.5f * float(granular::kBrickSize) * std::sqrt(3.0f) * glm::length(glm::vec3(depth_row));
  const float half = 0.5f * float(granular::kBrickSize);
  const float pixels_at_unit_depth = cell_pixels(view_projection, image_height, 1.0f);
  const std::size_t first_appended = rebuild.size();
  for (int z = 0; z < counts_.z; ++z)
    for (int y = 0; y < counts_.y; ++y)
      for (int x = 0; x < counts_.x; ++x) {
        const glm::vec4 centre(float(x) * granular::kBrickSize + half, float(y) * granular::kBrickSize + half,
                               float(z) * granular::kBrickSize + half, 1.0f);
        const float nearest = glm::dot(depth_row, centre) - brick_radius;
        const std::size_t index = std::size_t(x) + std::size_t(counts_.x) * (std::size_t(y) + std::size_t(counts_.y) * z);
        std::uint8_t& level = levels_[index];
        std::uint8_t wanted = level;
        if (nearest <= 0.0f) {
          wanted = kFine;
        } else {
          const float pixels = pixels_at_unit_depth / nearest;
          if (level == kFine && pixels < coarse_below_) wanted = kCoarse;
          if (level == kCoarse && pixels > coarse_below_ * kHysteresis) wanted = kFine;
        }
        if (wanted == level) continue;
        level = wanted;
        rebuild.push_back(std::uint32_t(index));
        const int around[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
        for (const auto& d : around) {
          const int nx = x + d[0], ny = y + d[1], nz = z + d[2];
          if (nx < 0 || ny < 0 || nz < 0 || nx >= counts_.x || ny >= counts_.y || nz >= counts_.z) continue;
          rebuild.push_back(std::uint32_t(nx + counts_.x * (ny + counts_.y * nz)));
        }
      }
  return rebuild.size() != first_appended;
}

}  // namespace viewer
