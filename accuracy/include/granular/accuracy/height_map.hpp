#pragma once
/// @file height_map.hpp
/// The height map of a grid: how many cells of a material each column holds, the surface the
/// accuracy suite's slope measurements fit.

#include <cstddef>
#include <vector>

#include "granular/grid.hpp"
#include "granular/material.hpp"

namespace granular::accuracy {

/// One value per column (x, y) of a grid, x fastest.
struct HeightMap {
  int nx = 0;              ///< columns along x
  int ny = 0;              ///< columns along y
  std::vector<double> h;   ///< nx * ny values, column (x, y) at x + nx y
  /// The value of column (x, y) (unchecked).
  double at(int x, int y) const { return h[std::size_t(x) + std::size_t(nx) * std::size_t(y)]; }
};

/// h(x, y) = the number of `material` cells in column (x, y) with floor_z <= z < nz (floor_z
/// below 0 counts from 0).
HeightMap height_map(const Grid& grid, int floor_z, Material material);

/// h(x, y) = the number of `material` cells stacked without a gap in column (x, y) from floor_z up:
/// a pile's height with whatever falls onto it from above left out.
HeightMap stacked_height_map(const Grid& grid, int floor_z, Material material);

}  // namespace granular::accuracy
