#pragma once
/// @file bricks.hpp
/// Bricks: the grid cut into cubes of kBrickSize cells, the unit in which a World tracks which
/// regions changed (for renderers and other consumers) and which regions it steps.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "granular/geometry.hpp"

namespace granular {

/// Edge length of a brick in cells. Bricks tile the grid from the origin; the last brick along an
/// axis may be partial. Even (blocks never straddle a brick boundary at offset 0) and at least 10
/// (the exactness argument of sparse stepping, docs/design/sparse-stepping.md).
inline constexpr int kBrickSize = 16;
static_assert(kBrickSize % 2 == 0 && kBrickSize >= 10, "see docs/design/sparse-stepping.md");

/// Bricks per axis for a grid of `size` cells.
constexpr Int3 brick_counts(Int3 size) {
  return {(size.x + kBrickSize - 1) / kBrickSize, (size.y + kBrickSize - 1) / kBrickSize,
          (size.z + kBrickSize - 1) / kBrickSize};
}

/// Every brick of a grid with `counts` bricks per axis (brick_counts), in index order.
inline std::vector<std::uint32_t> all_bricks(Int3 counts) {
  std::vector<std::uint32_t> bricks(std::size_t(counts.x) * std::size_t(counts.y) * std::size_t(counts.z));
  for (std::size_t i = 0; i < bricks.size(); ++i) bricks[i] = std::uint32_t(i);
  return bricks;
}

/// The cells of brick `index` (x fastest, then y, then z) in a grid of `size`, clipped to the grid.
constexpr Box brick_box(Int3 size, std::uint32_t index) {
  const Int3 n = brick_counts(size);
  const int bx = int(index % std::uint32_t(n.x)), by = int(index / std::uint32_t(n.x) % std::uint32_t(n.y)),
            bz = int(index / (std::uint32_t(n.x) * std::uint32_t(n.y)));
  const Box whole{{bx * kBrickSize, by * kBrickSize, bz * kBrickSize},
                  {(bx + 1) * kBrickSize, (by + 1) * kBrickSize, (bz + 1) * kBrickSize}};
  return intersect(whole, Box{{0, 0, 0}, size});
}

/// Cells in the bricks `bricks` (indices as brick_box takes them) of a grid of `size`.
constexpr std::uint64_t brick_cells(Int3 size, std::span<const std::uint32_t> bricks) {
  std::uint64_t cells = 0;
  for (const std::uint32_t b : bricks) cells += std::uint64_t(brick_box(size, b).volume());
  return cells;
}

/// How much of the grid the last step() call stepped. With sparse stepping a brick is stepped only
/// while it or a neighbour may change; with dense stepping every brick is stepped every tick.
struct ActivityStats {
  std::uint64_t active_bricks = 0;  ///< bricks stepped in the last tick
  std::uint64_t total_bricks = 0;   ///< bricks in the grid
  std::uint64_t active_cells = 0;   ///< cells inside the bricks stepped in the last tick
  std::uint64_t ticks = 0;          ///< ticks of the last step() call
  std::uint64_t brick_ticks = 0;    ///< bricks stepped, summed over the ticks of the last step() call
  std::uint64_t cell_ticks = 0;     ///< cells inside stepped bricks, summed over those ticks
};

}  // namespace granular
