#pragma once
/// @file raycast.hpp
/// Ray picking: the first non-void cell along a ray (3D DDA over the grid), for tools that act
/// where the player points (a mouse ray, a gun, a bucket).

#include <limits>
#include <optional>

#include "granular/geometry.hpp"
#include "granular/material.hpp"

namespace granular {

class Grid;
class World;

/// Where a ray first meets a non-void cell.
struct RayHit {
  Int3 cell;              ///< the first non-void cell along the ray
  Int3 normal;            ///< the outward normal of the face the ray entered `cell` through ({0,0,0} when the ray starts inside it)
  Vec3 point;             ///< where the ray enters `cell` (cell units)
  double distance = 0;    ///< from the origin to `point`, in cells along the unit direction
  Material material = Material::Void;  ///< the cell's material
  /// The cell in front of the hit face (cell + normal): where a placed cell goes. May lie outside the grid.
  Int3 in_front() const { return {cell.x + normal.x, cell.y + normal.y, cell.z + normal.z}; }
};

/// The first non-void cell of `world` that the ray from `origin` along `direction` (any non-zero
/// length) enters within `max_distance` cells, or nothing. The origin may lie outside the grid.
/// Reads the world brick by brick through World::read_region, so it works on every backend.
/// Throws InvalidArgument for a non-finite origin, a zero or non-finite direction, or a negative
/// max_distance.
std::optional<RayHit> raycast(const World& world, Vec3 origin, Vec3 direction,
                              double max_distance = std::numeric_limits<double>::infinity());

/// The same over a host grid.
std::optional<RayHit> raycast(const Grid& grid, Vec3 origin, Vec3 direction,
                              double max_distance = std::numeric_limits<double>::infinity());

}  // namespace granular
