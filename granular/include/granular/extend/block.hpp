#pragma once
/// @file extend/block.hpp
/// The 2x2x2 Margolus block: cell order, the 24-bit key of its 8 states, the 24-bit transition
/// (a permutation, encoded as in the paper), the offset cycle and the per-block random draw.
/// Everything here is plain integer arithmetic so every backend computes exactly the same values.

#include <array>
#include <cstdint>

namespace granular {

/// Cells of one block in block order. Cell i sits at (i & 1, (i >> 1) & 1, (i >> 2) & 1) relative to
/// the block's lowest corner: bit 0 is +x, bit 1 is +y, bit 2 is +z (up). Cells 0..3 are the bottom
/// layer, 4..7 the top layer.
using BlockCells = std::array<std::uint8_t, 8>;

/// The state of a whole block: cell i's 3-bit state at bits [3i, 3i+3). 8^8 = 16,777,216 keys.
using BlockKey = std::uint32_t;

/// A block transition: cell i moves to block position ((t >> 3i) & 7). Always a permutation.
using Transition = std::uint32_t;

/// Number of distinct block keys (8 states ^ 8 cells).
inline constexpr std::uint32_t kBlockKeyCount = 1u << 24;

/// The transition that leaves every cell where it is (cell i -> i).
inline constexpr Transition kIdentityTransition = 0xFAC688u;  // octal 76543210

/// Block-order index of the cell at offset (dx, dy, dz), each 0 or 1.
constexpr int block_cell(int dx, int dy, int dz) { return dx | (dy << 1) | (dz << 2); }

/// Packs 8 cell states (each < 8) into a key.
constexpr BlockKey encode_key(const BlockCells& cells) {
  BlockKey k = 0;
  for (int i = 0; i < 8; ++i) k |= BlockKey(cells[i] & 7u) << (3 * i);
  return k;
}

/// Unpacks a key into 8 cell states.
constexpr BlockCells decode_key(BlockKey key) {
  BlockCells c{};
  for (int i = 0; i < 8; ++i) c[i] = std::uint8_t((key >> (3 * i)) & 7u);
  return c;
}

/// Destination of cell i under transition t.
constexpr int destination(Transition t, int i) { return int((t >> (3 * i)) & 7u); }

/// Packs destinations (dest[i] = where cell i goes) into a transition.
constexpr Transition encode_transition(const std::array<std::uint8_t, 8>& dest) {
  Transition t = 0;
  for (int i = 0; i < 8; ++i) t |= Transition(dest[i] & 7u) << (3 * i);
  return t;
}

/// True when t's 24 bits name every destination exactly once and the unused high bits are zero.
constexpr bool is_permutation(Transition t) {
  if (t >> 24) return false;
  unsigned seen = 0;
  for (int i = 0; i < 8; ++i) seen |= 1u << destination(t, i);
  return seen == 0xFFu;
}

/// Applies t to the cells: out[dest(i)] = cells[i].
constexpr BlockCells apply_transition(const BlockCells& cells, Transition t) {
  BlockCells out{};
  for (int i = 0; i < 8; ++i) out[destination(t, i)] = cells[i];
  return out;
}

/// The 8 symmetries of the block about the vertical axis (the dihedral group D4), as maps from a
/// cell index to its image. Symmetry s mirrors x if bit 0 is set, mirrors y if bit 1 is set, and
/// then swaps x and y if bit 2 is set. Symmetry 0 is the identity.
constexpr std::array<std::uint8_t, 8> horizontal_symmetry(int s) {
  std::array<std::uint8_t, 8> map{};
  for (int i = 0; i < 8; ++i) {
    int x = i & 1, y = (i >> 1) & 1;
    const int z = (i >> 2) & 1;
    if (s & 1) x ^= 1;
    if (s & 2) y ^= 1;
    if (s & 4) { const int t = x; x = y; y = t; }
    map[i] = std::uint8_t(block_cell(x, y, z));
  }
  return map;
}

/// Where symmetry s sends cell i: horizontal_symmetry(s)[i], as arithmetic (no table).
constexpr int symmetry_image(int i, int s) {
  const int j = i ^ (s & 3);
  return (s & 4) ? (j & 4) | ((j & 1) << 1) | ((j >> 1) & 1) : j;
}

/// The cell symmetry s sends to cell j: the inverse of symmetry_image.
constexpr int symmetry_preimage(int j, int s) {
  const int k = (s & 4) ? (j & 4) | ((j & 1) << 1) | ((j >> 1) & 1) : j;
  return k ^ (s & 3);
}

/// The partition offset (0 or 1 per axis) of tick `tick`: z flips every tick (so a free grain
/// falls one cell per tick), x every 2 ticks, y every 4: all 8 offsets in an 8-tick cycle.
struct BlockOffset {
  int x, y, z;  ///< offset along each axis, 0 or 1
};

/// The offset of a tick in the 8-step cycle.
constexpr BlockOffset block_offset(std::uint64_t tick) {
  return {int((tick >> 1) & 1u), int((tick >> 2) & 1u), int(tick & 1u)};
}

/// Number of blocks along an axis of `extent` cells at partition offset `offset`. Block k starts at
/// cell 2k - offset; blocks that straddle the edge are included (their outside cells act as solid).
constexpr int block_count(int extent, int offset) { return (extent + offset + 1) / 2; }

/// The mixing function of block_random (SplitMix64's finaliser).
constexpr std::uint64_t random_mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// The part of block_random that depends on the seed alone (a step may compute it once).
constexpr std::uint64_t block_seed_key(std::uint64_t seed) { return random_mix(seed ^ 0x5EEDB10C5EEDB10Cull); }

/// What block_random_keyed adds to the packed position of a block of a world whose cell (0, 0, 0) is
/// cell `origin` of a larger world (WorldDef::domain_origin): with it, a part of a world draws what
/// the whole world draws at the same place. Every packed coordinate stays below 2^21 (grids are at
/// most kMaxGridExtent wide), so adding the packed origin adds each coordinate's.
constexpr std::uint64_t block_position_offset(int x, int y, int z) {
  return std::uint64_t(std::uint32_t(x)) | (std::uint64_t(std::uint32_t(y)) << 21) | (std::uint64_t(std::uint32_t(z)) << 42);
}

/// block_random from the seed's block_seed_key, for a world whose block_position_offset is `origin`.
constexpr std::uint64_t block_random_keyed(std::uint64_t seed_key, std::uint64_t tick, int x0, int y0, int z0,
                                           std::uint64_t origin = 0) {
  const std::uint64_t pos = block_position_offset(x0 + 1, y0 + 1, z0 + 1) + origin;
  return random_mix(seed_key + random_mix(tick * 0x9E3779B97F4A7C15ull + pos));
}

/// The 64-bit random word of the block whose lowest corner is (x0, y0, z0) (may be -1) at `tick`,
/// for rules with random choices. Deterministic for (seed, tick, position) on every backend.
constexpr std::uint64_t block_random(std::uint64_t seed, std::uint64_t tick, int x0, int y0, int z0) {
  return block_random_keyed(block_seed_key(seed), tick, x0, y0, z0);
}

/// Salt of the per-cycle draw of the offset order (keeps it independent of the per-block draws).
inline constexpr std::uint64_t kAxisOrderSalt = 0xA815C7C1E0FF5E75ull;

/// True when the 8-tick cycle holding `tick` walks its offsets with x and y exchanged (x flips
/// every 4 ticks, y every 2), drawn from block_random(seed ^ kAxisOrderSalt, tick / 8, -1, -1, -1):
/// a pure function of (seed, tick / 8), the same for every block of the cycle.
constexpr bool cycle_swaps_axes(std::uint64_t seed, std::uint64_t tick) {
  return (block_random(seed ^ kAxisOrderSalt, tick >> 3, -1, -1, -1) & 1u) != 0;
}

/// The offset of `tick` in its cycle, with x and y exchanged on the cycles cycle_swaps_axes draws
/// when `random_axis_order` is set (otherwise the paper's cycle, block_offset(tick)). Either way
/// all 8 offsets occur in every cycle, z flips every tick, and ticks 2k and 2k + 1 share x and y.
/// The paper's fixed order makes x flip twice as often as y, which leaves x/y-asymmetric piles
/// even under random block symmetry; drawing the order per cycle removes that bias.
constexpr BlockOffset block_offset(std::uint64_t tick, std::uint64_t seed, bool random_axis_order) {
  BlockOffset o = block_offset(tick);
  if (random_axis_order && cycle_swaps_axes(seed, tick)) {
    const int x = o.x;
    o.x = o.y;
    o.y = x;
  }
  return o;
}

}  // namespace granular
