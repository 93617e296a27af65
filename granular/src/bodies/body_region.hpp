#pragma once
/// @file body_region.hpp
/// The region a body is written in and its forces are read from, with the local numbering of its
/// cells that stamp_body and sand_forces share.

#include <cstddef>
#include <cstdint>

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
};

}  // namespace granular
