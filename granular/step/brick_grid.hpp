#pragma once
/// @file brick_grid.hpp
/// Which blocks of a tick belong to which brick, for sparse stepping. Plain constexpr integer
/// arithmetic, shared by the CPU and CUDA backends (docs/design/sparse-stepping.md).
///
/// Block k along an axis (origin 2k - offset, cells 2k - offset and 2k - offset + 1) is *owned* by
/// brick k / kBrickBlocks, the brick holding its upper cell 2k - offset + 1, whatever the offset;
/// the last brick along an axis also owns the one extra block that exists when the extent is a
/// multiple of kBrickSize and the offset is 1 (its upper cell lies outside the grid). A brick's
/// blocks therefore touch only its own cells and the one-cell layer below it on each axis (its
/// *footprint*), and every block has exactly one owner, so a tick steps a block iff its owner is
/// awake.

#include <cstdint>

#include "granular/bricks.hpp"
#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// Blocks per brick along an axis.
inline constexpr int kBrickBlocks = kBrickSize / 2;

/// A half-open range of block indices along one axis.
struct BlockSpan {
  int first;  ///< first block index
  int last;   ///< one past the last block index
};

/// The blocks along an axis of `extent` cells at partition offset `offset` owned by brick `brick`
/// of `bricks` bricks along that axis.
constexpr BlockSpan owned_blocks(int brick, int bricks, int extent, int offset) {
  const int count = block_count(extent, offset);
  const int first = brick * kBrickBlocks;
  const int last = brick + 1 == bricks ? count : (first + kBrickBlocks < count ? first + kBrickBlocks : count);
  return {first, last};
}

/// The brick along an axis holding cell coordinate `c` (0 <= c < extent).
constexpr int brick_of(int c) { return c / kBrickSize; }

/// Linear brick index (x fastest) of brick (bx, by, bz) in a grid of `bricks` bricks per axis.
constexpr std::uint32_t brick_index(Int3 bricks, int bx, int by, int bz) {
  return std::uint32_t((std::int64_t(bz) * bricks.y + by) * bricks.x + bx);
}

/// Brick coordinates of linear brick index `index` in a grid of `bricks` bricks per axis.
constexpr Int3 brick_coords(Int3 bricks, std::uint32_t index) {
  return {int(index % std::uint32_t(bricks.x)), int(index / std::uint32_t(bricks.x) % std::uint32_t(bricks.y)),
          int(index / (std::uint32_t(bricks.x) * std::uint32_t(bricks.y)))};
}

/// Cells of brick (bx, by, bz) inside a grid of `size` (partial bricks at the far edges).
constexpr std::uint64_t brick_cells(Int3 size, int bx, int by, int bz) {
  auto extent = [](int n, int b) {
    const int rest = n - b * kBrickSize;
    return std::uint64_t(rest < kBrickSize ? rest : kBrickSize);
  };
  return extent(size.x, bx) * extent(size.y, by) * extent(size.z, bz);
}

}  // namespace granular
