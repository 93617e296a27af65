#pragma once
/// @file cpu_block_row.hpp
/// One row of blocks (fixed y0 and z0) of a (sub-)step on the CPU, walked along x: the blocks inside
/// the grid eight at a time, the edge blocks with one cell column outside it, and rows of cells
/// outside the grid read from the context's outside row. Shared by the dense kernel (cpu_step.cpp)
/// and the sparse one (cpu_sparse_step.cpp); what a walk records of each block is its Notes policy.

#include <cstdint>

#include "cpu_block_ops.hpp"
#include "cpu_step.hpp"
#include "granular/block.hpp"

namespace granular::cpu_ops {

/// The four cell rows of a row of blocks, (y0, z0), (y0 + 1, z0), (y0, z0 + 1), (y0 + 1, z0 + 1):
/// row r holds bytes 2r and 2r + 1 of each block. A cell row outside the grid is the context's
/// outside row, read but never written.
struct BlockRow {
  std::uint8_t* cells[4];  ///< cell row r at x = 0
  std::uint64_t inside;    ///< the bytes of a block that lie in cell rows inside the grid
};

/// Every byte of a block lies in a cell row inside the grid.
inline constexpr std::uint64_t kWholeBlock = ~std::uint64_t(0);
/// The bytes of a block's cells with x = x0 (cells 0, 2, 4, 6).
inline constexpr std::uint64_t kLowColumn = 0x00FF00FF00FF00FFull;
/// The bytes of a block's cells with x = x0 + 1 (cells 1, 3, 5, 7).
inline constexpr std::uint64_t kHighColumn = 0xFF00FF00FF00FF00ull;

/// The row of blocks with lowest corner (., y0, z0); y0 and z0 may be -1 or the last cell.
inline BlockRow block_row(const StepContext& c, int y0, int z0) {
  const std::size_t sy = std::size_t(c.size.x), sz = sy * std::size_t(c.size.y);
  BlockRow row{};
  row.inside = 0;
  for (int r = 0; r < 4; ++r) {
    const int y = y0 + (r & 1), z = z0 + (r >> 1);
    if (y >= 0 && y < c.size.y && z >= 0 && z < c.size.z) {
      row.cells[r] = c.cells + sy * std::size_t(y) + sz * std::size_t(z);
      row.inside |= std::uint64_t(0xFFFFu) << (16 * r);
    } else {
      row.cells[r] = c.outside_row;
    }
  }
  return row;
}

/// Does nothing with a stepped block (the dense kernel).
struct NoNotes {
  /// `before`, `after`: the block's bytes; `inside`: those of its bytes that are cells of the grid.
  void block(std::uint64_t, std::uint64_t, std::uint64_t) {}
};

/// The bytes of the block at x0 (both its cell columns inside the grid).
inline std::uint64_t load_block(const BlockRow& row, int x0) {
  return load_pair(row.cells[0] + x0) | (load_pair(row.cells[1] + x0) << 16) | (load_pair(row.cells[2] + x0) << 32) |
         (load_pair(row.cells[3] + x0) << 48);
}

/// Steps the block at x0 (both its cell columns inside the grid). With kWhole (every cell row inside)
/// the store is branch-free: a block that stays rewrites its own bytes.
template <bool kWhole, class Rule, class Notes>
inline void step_block_at(const Rule& rule, const BlockRow& row, int x0, int y0, int z0, Notes& notes) {
  const std::uint64_t v = load_block(row, x0);
  const std::uint64_t out = rule.step(v, x0, y0, z0);
  for (int r = 0; r < 4; ++r)
    if (kWhole || ((row.inside >> (16 * r)) & 1u)) store_pair(row.cells[r] + x0, out >> (16 * r));
  notes.block(v, out, kWhole ? kWholeBlock : row.inside);
}

/// Steps the block at x0 = -1 (cell column x0 outside the grid, read as the rule's outside state).
template <class Rule, class Notes>
inline void step_low_edge_block(const Rule& rule, const BlockRow& row, int y0, int z0, Notes& notes) {
  const std::uint64_t outside = std::uint64_t(rule.outside & 0xFFu);
  std::uint64_t v = 0;
  for (int r = 0; r < 4; ++r) v |= (outside | (std::uint64_t(row.cells[r][0]) << 8)) << (16 * r);
  const std::uint64_t out = rule.step(v, -1, y0, z0);
  const std::uint64_t inside = row.inside & kHighColumn;
  if (((v ^ out) & inside) != 0)
    for (int r = 0; r < 4; ++r)
      if ((row.inside >> (16 * r)) & 1u) row.cells[r][0] = std::uint8_t(out >> (16 * r + 8));
  notes.block(v, out, inside);
}

/// Steps the block at x0 = size.x - 1 (cell column x0 + 1 outside the grid).
template <class Rule, class Notes>
inline void step_high_edge_block(const Rule& rule, const BlockRow& row, int x0, int y0, int z0, Notes& notes) {
  const std::uint64_t outside = std::uint64_t(rule.outside & 0xFFu);
  std::uint64_t v = 0;
  for (int r = 0; r < 4; ++r) v |= (std::uint64_t(row.cells[r][x0]) | (outside << 8)) << (16 * r);
  const std::uint64_t out = rule.step(v, x0, y0, z0);
  const std::uint64_t inside = row.inside & kLowColumn;
  if (((v ^ out) & inside) != 0)
    for (int r = 0; r < 4; ++r)
      if ((row.inside >> (16 * r)) & 1u) row.cells[r][x0] = std::uint8_t(out >> (16 * r));
  notes.block(v, out, inside);
}

/// True when the eight blocks at x, x + 2, ..., x + 14 (inside the grid along x) need no step: their
/// 64 cells are equal and the rule says such a block does not change. Such blocks are quiet too.
template <class Rule>
inline bool group_stays(const Rule& rule, const BlockRow& row, int x) {
  const std::uint64_t ref = (std::uint64_t(row.cells[0][x]) & 0xFFu) * kEveryByte;
  std::uint64_t diff = 0;
  for (int r = 0; r < 4; ++r) diff |= (load_word(row.cells[r] + x) ^ ref) | (load_word(row.cells[r] + x + 8) ^ ref);
  return diff == 0 && !rule.steps_uniform(row.cells[0][x]);
}

/// Steps the blocks at x, x + 2, ... below x_end (all inside the grid along x), eight at a time
/// where group_stays lets a group pass.
template <bool kWhole, class Rule, class Notes>
inline void step_blocks(const Rule& rule, const BlockRow& row, int x, int x_end, int y0, int z0, Notes& notes) {
  for (; x + 16 <= x_end; x += 16) {
    if (group_stays(rule, row, x)) continue;
    for (int k = 0; k < 16; k += 2) step_block_at<kWhole>(rule, row, x + k, y0, z0, notes);
  }
  for (; x < x_end; x += 2) step_block_at<kWhole>(rule, row, x, y0, z0, notes);
}

/// One past the last start below `stop` of a block that lies inside the grid along x, for blocks
/// starting at x, x + 2, ... (x >= 0).
inline int inside_end(const StepContext& c, int x, int stop) {
  const int end = x + ((c.size.x - x) / 2) * 2;
  return end < stop ? end : stop;
}

}  // namespace granular::cpu_ops
