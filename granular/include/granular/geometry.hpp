#pragma once
/// @file geometry.hpp
/// Small value types for grid coordinates and tool regions. Coordinates are in cells; z is up.

#include <cstdint>
#include <limits>

namespace granular {

/// Integer cell coordinate or grid extent.
struct Int3 {
  int x = 0;  ///< x (first, fastest-varying axis)
  int y = 0;  ///< y
  int z = 0;  ///< z (vertical, gravity points to -z)
  friend constexpr bool operator==(const Int3&, const Int3&) = default;
};

/// Real-valued position in cell units: cell (i,j,k) spans [i,i+1) x [j,j+1) x [k,k+1).
struct Vec3 {
  double x = 0;  ///< x
  double y = 0;  ///< y
  double z = 0;  ///< z (up)
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

/// Axis-aligned box of cells: min inclusive, max exclusive.
struct Box {
  Int3 min;  ///< first cell inside
  Int3 max;  ///< one past the last cell inside
  /// True when the box holds no cell.
  constexpr bool empty() const { return max.x <= min.x || max.y <= min.y || max.z <= min.z; }
  /// Number of cells in the box (0 when empty; INT64_MAX when the count does not fit in it, as for a box
  /// spanning all of int on every axis).
  constexpr std::int64_t volume() const {
    if (empty()) return 0;
    constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
    const std::int64_t ex = std::int64_t(max.x) - min.x, ey = std::int64_t(max.y) - min.y,
                       ez = std::int64_t(max.z) - min.z;  // each < 2^32
    if (ex > kMax / ey) return kMax;
    const std::int64_t exy = ex * ey;
    return exy > kMax / ez ? kMax : exy * ez;
  }
  /// Extent per axis (for a box whose extents fit in int, as every box inside a grid does).
  constexpr Int3 extent() const { return {max.x - min.x, max.y - min.y, max.z - min.z}; }
  friend constexpr bool operator==(const Box&, const Box&) = default;
};

/// A sphere in cell units; a cell belongs to it when the cell's centre lies within the radius.
struct Sphere {
  Vec3 center;        ///< centre, in cell units
  double radius = 1;  ///< radius, in cells (> 0)
};

/// Intersection of two boxes (empty box when they do not overlap).
constexpr Box intersect(const Box& a, const Box& b) {
  auto mx = [](int p, int q) { return p > q ? p : q; };
  auto mn = [](int p, int q) { return p < q ? p : q; };
  return {{mx(a.min.x, b.min.x), mx(a.min.y, b.min.y), mx(a.min.z, b.min.z)},
          {mn(a.max.x, b.max.x), mn(a.max.y, b.max.y), mn(a.max.z, b.max.z)}};
}

}  // namespace granular
