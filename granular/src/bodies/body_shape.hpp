#pragma once
/// @file body_shape.hpp
/// A body's shape at a pose, as the grid sees it: the cells whose centres lie inside it.

#include <cstdint>
#include <vector>

#include "granular/body.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// A rotation matrix, rows of the world frame in the body's axes.
struct Rotation {
  double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  ///< m[i][j]: world axis i of body axis j
  /// The rotation of the unit quaternion `q` (normalised here; the identity for a zero one).
  static Rotation of(const Quat& q);
  /// World vector of body vector `v`.
  Vec3 apply(const Vec3& v) const;
  /// Body vector of world vector `v`.
  Vec3 inverse(const Vec3& v) const;
};

/// A body's shape placed at a pose: its cells and their bounds.
class PlacedShape {
 public:
  /// `def`'s shape at `pose` (def.pose is not read).
  PlacedShape(const BodyDef& def, const BodyPose& pose);
  /// The cells whose centres may lie inside, clipped to a grid of `size` (empty when it misses it).
  Box bounds(Int3 size) const;
  /// The grid indices (x + size.x * (y + size.y * z)), ascending, of the cells of a grid of `size`
  /// whose centres lie inside (its surface included), into `out` (cleared first).
  void cells(Int3 size, std::vector<std::uint64_t>& out) const;

 private:
  BodyShape shape_;
  Vec3 half_;          ///< Box: half extents
  double radius_ = 0;  ///< Sphere, Capsule
  double half_length_ = 0;
  Vec3 centre_;
  Rotation rotation_;
};

/// The grid index of cell (x, y, z) in a grid of `size`.
constexpr std::uint64_t grid_index(Int3 size, int x, int y, int z) {
  return std::uint64_t(x) + std::uint64_t(size.x) * (std::uint64_t(y) + std::uint64_t(size.y) * std::uint64_t(z));
}

/// The cell of grid index `i` in a grid of `size`.
constexpr Int3 grid_cell(Int3 size, std::uint64_t i) {
  const std::uint64_t row = i / std::uint64_t(size.x);
  return {int(i % std::uint64_t(size.x)), int(row % std::uint64_t(size.y)), int(row / std::uint64_t(size.y))};
}

}  // namespace granular
