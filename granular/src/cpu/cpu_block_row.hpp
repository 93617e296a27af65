#pragma once
/// @file cpu_block_row.hpp
/// One row of blocks (fixed y0 and z0) of a (sub-)step on the CPU, walked along x: the blocks inside
/// the grid eight at a time, the edge blocks with one cell column outside it, and rows of cells
/// outside the grid read from the context's outside row. Shared by the dense kernel (cpu_step.cpp)
/// and the sparse one (cpu_sparse_step.cpp); what a walk records of each block is its Notes policy.

#include <cstdint>

#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#define GRANULAR_ROW_SSE2 1  // step_group moves cell rows in 16-byte SSE2 registers (x86-64)
#endif

#include "cpu/cpu_block_ops.hpp"
#include "cpu/cpu_step.hpp"
#include "granular/extend/block.hpp"

namespace granular::cpu_ops {

/// The four cell rows of a row of blocks, (y0, z0), (y0 + 1, z0), (y0, z0 + 1), (y0 + 1, z0 + 1):
/// row r holds bytes 2r and 2r + 1 of each block. A cell row outside the grid is the context's
/// outside row, read but never written.
struct BlockRow {
  std::uint8_t* cells[4];  ///< cell row r at x = 0
  std::uint64_t inside;    ///< the bytes of a block that lie in cell rows inside the grid
  std::uint8_t* side[4];   ///< the side plane's row r at x = 0 (StepContext::side; null without)
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
      row.side[r] = c.side != nullptr ? c.side + sy * std::size_t(y) + sz * std::size_t(z) : nullptr;
      row.inside |= std::uint64_t(0xFFFFu) << (16 * r);
    } else {
      row.cells[r] = c.outside_row;
      row.side[r] = c.outside_side_row;
    }
  }
  return row;
}

/// Does nothing with stepped blocks (the dense kernel). A Notes policy is handed the blocks a walk
/// steps, in order along x: a group of eight at once, or one.
struct NoNotes {
  /// The blocks at x0, x0 + 2, ... (count of them): `before[k]`, `after[k]` their bytes; `inside`:
  /// those of their bytes that are cells of the grid; `side_before`, `side_after` their side bytes
  /// (null when the rule steps no side plane).
  void blocks(int, const std::uint64_t*, const std::uint64_t*, int, std::uint64_t, const std::uint64_t* = nullptr,
              const std::uint64_t* = nullptr) {}
};

/// The bytes of the block at x0 of the rows `rows` (both its cell columns inside the grid).
inline std::uint64_t load_block(std::uint8_t* const (&rows)[4], int x0) {
  return load_pair(rows[0] + x0) | (load_pair(rows[1] + x0) << 16) | (load_pair(rows[2] + x0) << 32) |
         (load_pair(rows[3] + x0) << 48);
}

/// The bytes of the block at x0 (both its cell columns inside the grid).
inline std::uint64_t load_block(const BlockRow& row, int x0) { return load_block(row.cells, x0); }

/// Steps the block at x0 (both its cell columns inside the grid), and its side bytes when the rule
/// steps a side plane. With kWhole (every cell row inside) the store is branch-free: a block that
/// stays rewrites its own bytes.
template <bool kWhole, class Rule, class Notes>
inline void step_block_at(const Rule& rule, const BlockRow& row, int x0, int y0, int z0, Notes& notes) {
  const std::uint64_t v = load_block(row, x0);
  if constexpr (Rule::kStepsSide) {
    const std::uint64_t side_before = load_block(row.side, x0);
    std::uint64_t side = side_before;
    const std::uint64_t out = rule.step(v, side, x0, y0, z0);
    for (int r = 0; r < 4; ++r)
      if (kWhole || ((row.inside >> (16 * r)) & 1u)) {
        store_pair(row.cells[r] + x0, out >> (16 * r));
        store_pair(row.side[r] + x0, side >> (16 * r));
      }
    notes.blocks(x0, &v, &out, 1, kWhole ? kWholeBlock : row.inside, &side_before, &side);
  } else {
    const std::uint64_t out = rule.step(v, x0, y0, z0);
    for (int r = 0; r < 4; ++r)
      if (kWhole || ((row.inside >> (16 * r)) & 1u)) store_pair(row.cells[r] + x0, out >> (16 * r));
    notes.blocks(x0, &v, &out, 1, kWhole ? kWholeBlock : row.inside);
  }
}

/// An edge block's bytes before and after its step, and those of its bytes that are grid cells.
struct EdgeBlock {
  std::uint64_t before;  ///< the bytes before (outside cells as the rule's outside state)
  std::uint64_t after;   ///< the bytes after
  std::uint64_t inside;  ///< the bytes that are cells of the grid (the ones written)
  std::uint64_t side_before = 0;  ///< the side bytes before (0 outside the grid; rules that step a side plane)
  std::uint64_t side_after = 0;   ///< the side bytes after
};

/// Steps the edge block at x0 = -1 (cell column x0 outside the grid) or x0 = size.x - 1 (cell
/// column x0 + 1 outside): the outside column reads as the rule's outside state and is never
/// written. Out of line: at most two a row, they stay out of the walk's loops.
template <class Rule>
[[gnu::noinline]] EdgeBlock step_edge(const Rule& rule, const BlockRow& row, int x0, int y0, int z0) {
  const bool low = x0 < 0;
  const int x = low ? 0 : x0;                   // the block's cell column inside the grid
  const unsigned inside_shift = low ? 8u : 0u;  // its bytes' place in each 16-bit row pair
  const std::uint64_t outside = std::uint64_t(rule.outside & 0xFFu) << (8u - inside_shift);
  std::uint64_t v = 0;
  for (int r = 0; r < 4; ++r) v |= ((std::uint64_t(row.cells[r][x]) << inside_shift) | outside) << (16 * r);
  const std::uint64_t inside = row.inside & (low ? kHighColumn : kLowColumn);
  if constexpr (Rule::kStepsSide) {
    std::uint64_t side_before = 0;
    for (int r = 0; r < 4; ++r) side_before |= (std::uint64_t(row.side[r][x]) << inside_shift) << (16 * r);
    std::uint64_t side = side_before;
    const std::uint64_t out = rule.step(v, side, x0, y0, z0);
    if ((((v ^ out) | (side_before ^ side)) & inside) != 0)
      for (int r = 0; r < 4; ++r)
        if ((row.inside >> (16 * r)) & 1u) {
          row.cells[r][x] = std::uint8_t(out >> (16 * r + int(inside_shift)));
          row.side[r][x] = std::uint8_t(side >> (16 * r + int(inside_shift)));
        }
    return {v, out, inside, side_before, side};
  } else {
    const std::uint64_t out = rule.step(v, x0, y0, z0);
    if (((v ^ out) & inside) != 0)
      for (int r = 0; r < 4; ++r)
        if ((row.inside >> (16 * r)) & 1u) row.cells[r][x] = std::uint8_t(out >> (16 * r + int(inside_shift)));
    return {v, out, inside};
  }
}

/// Steps the edge block at x0 (-1 or size.x - 1) and hands it to `notes`.
template <class Rule, class Notes>
inline void step_edge_block(const Rule& rule, const BlockRow& row, int x0, int y0, int z0, Notes& notes) {
  const EdgeBlock e = step_edge(rule, row, x0, y0, z0);
  if constexpr (Rule::kStepsSide)
    notes.blocks(x0, &e.before, &e.after, 1, e.inside, &e.side_before, &e.side_after);
  else
    notes.blocks(x0, &e.before, &e.after, 1, e.inside);
}

/// Steps the eight blocks at x, x + 2, ..., x + 14 (inside the grid along x), unless their 64 cells
/// are equal and the rule says such a block does not change (such blocks are quiet too); a group
/// that stays as it was is not stored. With SSE2 the 16 bytes of each cell row are loaded once and
/// transposed into the blocks' bytes, and back.
template <bool kWhole, class Rule, class Notes>
inline void step_group(const Rule& rule, const BlockRow& row, int x, int y0, int z0, Notes& notes) {
  if constexpr (Rule::kStepsSide) {  // a side plane is stepped block by block
    for (int k = 0; k < 8; ++k) step_block_at<kWhole>(rule, row, x + 2 * k, y0, z0, notes);
    return;
  }
  const std::uint64_t inside = kWhole ? kWholeBlock : row.inside;
  std::uint64_t in[8], out[8];
#ifdef GRANULAR_ROW_SSE2
  const auto load_row = [&](int r) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(row.cells[r] + x)); };
  const __m128i r0 = load_row(0), r1 = load_row(1), r2 = load_row(2), r3 = load_row(3);
  const __m128i ref = _mm_set1_epi8(char(row.cells[0][x]));
  const __m128i equal = _mm_and_si128(_mm_and_si128(_mm_cmpeq_epi8(r0, ref), _mm_cmpeq_epi8(r1, ref)),
                                      _mm_and_si128(_mm_cmpeq_epi8(r2, ref), _mm_cmpeq_epi8(r3, ref)));
  if (_mm_movemask_epi8(equal) == 0xFFFF && !rule.steps_uniform(row.cells[0][x])) return;
  // 16-bit pairs of rows 0 and 1 side by side (a: blocks 0..3, b: 4..7), of rows 2 and 3 (c, d);
  // then the 32-bit halves of each block side by side: one block per 64-bit lane.
  const __m128i a = _mm_unpacklo_epi16(r0, r1), b = _mm_unpackhi_epi16(r0, r1);
  const __m128i c = _mm_unpacklo_epi16(r2, r3), d = _mm_unpackhi_epi16(r2, r3);
  const __m128i blocks[4] = {_mm_unpacklo_epi32(a, c), _mm_unpackhi_epi32(a, c), _mm_unpacklo_epi32(b, d),
                             _mm_unpackhi_epi32(b, d)};
  for (int k = 0; k < 4; ++k) {
    in[2 * k] = std::uint64_t(_mm_cvtsi128_si64(blocks[k]));
    in[2 * k + 1] = std::uint64_t(_mm_cvtsi128_si64(_mm_unpackhi_epi64(blocks[k], blocks[k])));
  }
#else
  const std::uint64_t ref = (std::uint64_t(row.cells[0][x]) & 0xFFu) * kEveryByte;
  std::uint64_t diff = 0;
  for (int r = 0; r < 4; ++r) diff |= (load_word(row.cells[r] + x) ^ ref) | (load_word(row.cells[r] + x + 8) ^ ref);
  if (diff == 0 && !rule.steps_uniform(row.cells[0][x])) return;
  for (int k = 0; k < 8; ++k) in[k] = load_block(row, x + 2 * k);
#endif
  std::uint64_t changed = 0;
  for (int k = 0; k < 8; ++k) {
    out[k] = rule.step(in[k], x + 2 * k, y0, z0);
    changed |= in[k] ^ out[k];
  }
  notes.blocks(x, in, out, 8, inside);
  if (changed == 0) return;  // the cells stay as they are
#ifdef GRANULAR_ROW_SSE2
  // The inverse: 32-bit halves back to rows 0 and 1 (pairs A) and rows 2 and 3 (pairs C), then
  // the 16-bit pairs of each row together.
  const auto lanes = [&](int k) { return _mm_set_epi64x(std::int64_t(out[2 * k + 1]), std::int64_t(out[2 * k])); };
  const auto halves = [](__m128i first, __m128i second, __m128i& pairs_a, __m128i& pairs_c) {
    const __m128i lo = _mm_unpacklo_epi32(first, second), hi = _mm_unpackhi_epi32(first, second);
    pairs_a = _mm_unpacklo_epi32(lo, hi);
    pairs_c = _mm_unpackhi_epi32(lo, hi);
  };
  const auto split = [](__m128i v) {  // [p0 q0 p1 q1 p2 q2 p3 q3] -> [p0 p1 p2 p3 q0 q1 q2 q3]
    v = _mm_shufflehi_epi16(_mm_shufflelo_epi16(v, _MM_SHUFFLE(3, 1, 2, 0)), _MM_SHUFFLE(3, 1, 2, 0));
    return _mm_shuffle_epi32(v, _MM_SHUFFLE(3, 1, 2, 0));
  };
  __m128i pa_lo, pc_lo, pa_hi, pc_hi;
  halves(lanes(0), lanes(1), pa_lo, pc_lo);
  halves(lanes(2), lanes(3), pa_hi, pc_hi);
  const __m128i s01_lo = split(pa_lo), s01_hi = split(pa_hi), s23_lo = split(pc_lo), s23_hi = split(pc_hi);
  const __m128i rows[4] = {_mm_unpacklo_epi64(s01_lo, s01_hi), _mm_unpackhi_epi64(s01_lo, s01_hi),
                           _mm_unpacklo_epi64(s23_lo, s23_hi), _mm_unpackhi_epi64(s23_lo, s23_hi)};
  for (int r = 0; r < 4; ++r)
    if (kWhole || ((row.inside >> (16 * r)) & 1u))
      _mm_storeu_si128(reinterpret_cast<__m128i*>(row.cells[r] + x), rows[r]);
#else
  for (int k = 0; k < 8; ++k)
    for (int r = 0; r < 4; ++r)
      if (kWhole || ((row.inside >> (16 * r)) & 1u)) store_pair(row.cells[r] + x + 2 * k, out[k] >> (16 * r));
#endif
}

/// Steps the blocks at x, x + 2, ... below x_end (all inside the grid along x), eight at a time
/// (step_group) while eight remain.
template <bool kWhole, class Rule, class Notes>
inline void step_blocks(const Rule& rule, const BlockRow& row, int x, int x_end, int y0, int z0, Notes& notes) {
  for (; x + 16 <= x_end; x += 16) step_group<kWhole>(rule, row, x, y0, z0, notes);
  for (; x < x_end; x += 2) step_block_at<kWhole>(rule, row, x, y0, z0, notes);
}

/// One past the last start below `stop` of a block that lies inside the grid along x, for blocks
/// starting at x, x + 2, ... (x >= 0).
inline int inside_end(const StepContext& c, int x, int stop) {
  const int end = x + ((c.size.x - x) / 2) * 2;
  return end < stop ? end : stop;
}

}  // namespace granular::cpu_ops
