#pragma once
/// @file body_region.hpp
/// The region a body is written in and its forces are read from, with the local numbering of its
/// cells that stamp_body and sand_forces share, the coordinates of a body's cells, and the
/// surroundings of its layers.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
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
};

/// The surroundings of a set of cells of `region`, layer by layer: calls fn(i, z) once for the local
/// index i, in layer z of the region (0 its first), of each cell of the region not in the set that
/// lies within `reach` cells in x and in y
/// of an edge cell of the set in the same layer (a cell of it with a side neighbour in its layer
/// outside the set or the region). `cells` are the set's cells (each in the region); `rows` is
/// scratch. Works on bit rows (a bit a cell along x): the edges, widened by `reach` along x, then
/// across rows.
template <class Fn>
void for_each_cell_beside(const BodyRegion& region, std::span<const Int3> cells, int reach,
                          std::vector<std::uint64_t>& rows, Fn&& fn) {
  if (cells.empty()) return;
  int low = region.box.max.z, high = region.box.min.z - 1;
  for (const Int3 c : cells) {
    low = std::min(low, c.z);
    high = std::max(high, c.z);
  }
  const std::size_t words = (std::size_t(region.e.x) + 63) / 64, ny = std::size_t(region.e.y);
  const std::size_t layer = ny * words, layers = std::size_t(high - low + 1);
  // The set's rows, layer after layer from `low`, then a layer's edges widened along x.
  rows.assign((layers + 1) * layer, 0);
  std::uint64_t* wide = rows.data() + layers * layer;
  for (const Int3 c : cells) {
    const std::size_t x = std::size_t(c.x - region.box.min.x);
    rows[std::size_t(c.z - low) * layer + std::size_t(c.y - region.box.min.y) * words + x / 64] |= std::uint64_t(1)
                                                                                                   << (x % 64);
  }
  const std::uint64_t last_word =
      region.e.x % 64 == 0 ? ~std::uint64_t(0) : (std::uint64_t(1) << (region.e.x % 64)) - 1;
  for (std::size_t z = 0; z < layers; ++z) {
    const std::uint64_t* in = rows.data() + z * layer;
    for (std::size_t y = 0; y < ny; ++y) {
      const std::uint64_t* row = in + y * words;
      for (std::size_t w = 0; w < words; ++w) {
        const std::uint64_t left = row[w] << 1 | (w > 0 ? row[w - 1] >> 63 : 0);  // bit x: cell x - 1 in the set
        const std::uint64_t right = row[w] >> 1 | (w + 1 < words ? row[w + 1] << 63 : 0);
        const std::uint64_t down = y > 0 ? row[w - words] : 0, up = y + 1 < ny ? row[w + words] : 0;
        wide[y * words + w] = row[w] & ~(left & right & down & up);
      }
      for (int k = 0; k < reach; ++k) {
        std::uint64_t carry = 0;  // the bit shifted up out of the word before
        for (std::size_t w = 0; w < words; ++w) {
          std::uint64_t& m = wide[y * words + w];
          const std::uint64_t next = w + 1 < words ? wide[y * words + w + 1] : 0;
          const std::uint64_t grown = m | m << 1 | carry | m >> 1 | next << 63;
          carry = m >> 63;
          m = grown;
        }
      }
    }
    const std::uint32_t first = region.local({region.box.min.x, region.box.min.y, low + int(z)});
    for (std::size_t y = 0; y < ny; ++y)
      for (std::size_t w = 0; w < words; ++w) {
        std::uint64_t near = 0;
        for (std::size_t from = y >= std::size_t(reach) ? y - std::size_t(reach) : 0;
             from <= std::min(ny - 1, y + std::size_t(reach)); ++from)
          near |= wide[from * words + w];
        near &= ~in[y * words + w] & (w + 1 == words ? last_word : ~std::uint64_t(0));
        for (; near != 0; near &= near - 1)
          fn(first + std::uint32_t(y * std::size_t(region.e.x) + w * 64 + std::size_t(std::countr_zero(near))),
             low - region.box.min.z + int(z));
      }
  }
}

/// Calls fn(c) with the cell c of each grid index of `cells` (ascending, of a grid of `grid`) in
/// turn, stepping along a row where the next index lies in it rather than dividing.
template <class Fn>
void for_each_cell_at(const std::vector<std::uint64_t>& cells, Int3 grid, Fn&& fn) {
  Int3 c{};
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (k > 0 && cells[k] - cells[k - 1] < std::uint64_t(grid.x - c.x))
      c.x += int(cells[k] - cells[k - 1]);
    else
      c = grid_cell(grid, cells[k]);
    fn(c);
  }
}

/// The cells of the grid indices `cells` (ascending, of a grid of `grid`), into `out`.
inline void cells_at(const std::vector<std::uint64_t>& cells, Int3 grid, std::vector<Int3>& out) {
  out.resize(cells.size());
  std::size_t k = 0;
  for_each_cell_at(cells, grid, [&](Int3 c) { out[k++] = c; });
}

}  // namespace granular
