#pragma once
/// @file body_region.hpp
/// The region a body is written in and its forces are read from, with the local numbering of its
/// cells that stamp_body and sand_forces share, and the coordinates of a body's cells.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bodies/body_shape.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// The region a body is written in: a box of the grid, its cells numbered x fastest (local indices).
struct BodyRegion {
  Box box;  ///< the cells, in grid coordinates
  Int3 e;   ///< its extent
  /// The region of `b`.
  explicit BodyRegion(const Box& b) : box(b), e(b.extent()) {}
  /// The local index of cell `c` (inside()).
  std::uint32_t local(Int3 c) const {
    return std::uint32_t((std::size_t(c.z - box.min.z) * std::size_t(e.y) + std::size_t(c.y - box.min.y)) *
                             std::size_t(e.x) +
                         std::size_t(c.x - box.min.x));
  }
  /// The cell of local index `i`.
  Int3 cell(std::uint32_t i) const {
    const std::uint32_t row = i / std::uint32_t(e.x);
    return {box.min.x + int(i % std::uint32_t(e.x)), box.min.y + int(row % std::uint32_t(e.y)),
            box.min.z + int(row / std::uint32_t(e.y))};
  }
  /// True when cell `c` lies in the region.
  bool inside(Int3 c) const {
    return c.x >= box.min.x && c.y >= box.min.y && c.z >= box.min.z && c.x < box.max.x && c.y < box.max.y &&
           c.z < box.max.z;
  }
  /// Its cells.
  std::size_t volume() const { return std::size_t(e.x) * std::size_t(e.y) * std::size_t(e.z); }
  /// Calls fn(first, count) for each row (local index of its first cell, and its cells along x) of
  /// the cells of the region within `reach` cells of cell `c` in x and y, in c's layer.
  template <class Fn>
  void for_each_row_beside(Int3 c, int reach, Fn&& fn) const {
    const int x0 = std::max(c.x - reach, box.min.x), x1 = std::min(c.x + reach, box.max.x - 1);
    for (int y = std::max(c.y - reach, box.min.y); y <= std::min(c.y + reach, box.max.y - 1); ++y)
      fn(local({x0, y, c.z}), x1 - x0 + 1);
  }
};

/// The cells `cells` (ascending grid indices of a grid of `grid`) as coordinates, into `out`: one
/// division per run of cells along x, not one per cell.
inline void cells_at(const std::vector<std::uint64_t>& cells, Int3 grid, std::vector<Int3>& out) {
  out.resize(cells.size());
  Int3 c{};
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (k > 0 && cells[k] - cells[k - 1] < std::uint64_t(grid.x - c.x))
      c.x += int(cells[k] - cells[k - 1]);
    else
      c = grid_cell(grid, cells[k]);
    out[k] = c;
  }
}

}  // namespace granular
