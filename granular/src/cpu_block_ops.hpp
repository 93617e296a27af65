#pragma once
/// @file cpu_block_ops.hpp
/// The CPU kernels' block primitives: loading and storing cell pairs, packing 8 cell bytes to a
/// key and back, and the key after a tick's rule (with the random symmetry). Shared by the dense
/// kernel (cpu_step.cpp) and the sparse one (cpu_sparse_step.cpp).

#include <array>
#include <cstdint>
#include <cstring>

#include "cpu_step.hpp"
#include "granular/block.hpp"
#include "granular/material.hpp"

namespace granular::cpu_ops {

/// One in every byte of a word.
inline constexpr std::uint64_t kEveryByte = 0x0101010101010101ull;
/// The state of a cell outside the grid (solid).
inline constexpr std::uint64_t kOutsideCell = to_cell(Material::Solid);

/// A horizontal symmetry acting on 24-bit keys: each cell's 3 bits move as a unit, so the key is a
/// bit permutation, applied as three byte-indexed partial tables.
struct KeySymmetries {
  BlockKey forward[8][3][256];  ///< per symmetry and key byte: that byte's bits moved into the frame
  BlockKey inverse[8][3][256];  ///< the same for the inverse symmetry (back from the frame)
};

/// Builds the forward and inverse key tables of the 8 symmetries.
constexpr KeySymmetries make_key_symmetries() {
  KeySymmetries t{};
  for (int s = 0; s < 8; ++s) {
    const auto map = horizontal_symmetry(s);
    std::array<int, 8> inv{};
    for (int i = 0; i < 8; ++i) inv[map[i]] = i;
    for (int part = 0; part < 3; ++part)
      for (int byte = 0; byte < 256; ++byte) {
        BlockKey fwd = 0, back = 0;
        for (int b = 0; b < 8; ++b) {
          if (!((byte >> b) & 1)) continue;
          const int bit = part * 8 + b, cell = bit / 3, lane = bit % 3;
          fwd |= BlockKey(1) << (3 * map[cell] + lane);
          back |= BlockKey(1) << (3 * inv[cell] + lane);
        }
        t.forward[s][part][byte] = fwd;
        t.inverse[s][part][byte] = back;
      }
  }
  return t;
}

/// The key symmetries, built at compile time.
inline const KeySymmetries kKeySymmetry = make_key_symmetries();

/// Applies a key symmetry table to a key.
inline BlockKey permute_key(BlockKey k, const BlockKey (&table)[3][256]) {
  return table[0][k & 0xFFu] | table[1][(k >> 8) & 0xFFu] | table[2][k >> 16];
}

/// Loads 2 cell bytes (any alignment).
inline std::uint64_t load_pair(const std::uint8_t* p) {
  std::uint16_t v;
  std::memcpy(&v, p, 2);
  return v;
}

/// Stores 2 cell bytes (any alignment).
inline void store_pair(std::uint8_t* p, std::uint64_t v) {
  const auto w = std::uint16_t(v);
  std::memcpy(p, &w, 2);
}

/// Loads 8 cell bytes (any alignment).
inline std::uint64_t load_word(const std::uint8_t* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
}

/// The block's 8 bytes (cell i in byte i, each < 8) packed to its 24-bit key.
inline BlockKey pack_key(std::uint64_t v) {
  std::uint64_t t = (v | (v >> 5)) & 0x003F003F003F003Full;
  t = (t | (t >> 10)) & 0x00000FFF00000FFFull;
  return BlockKey((t | (t >> 20)) & 0xFFFFFFu);
}

/// The inverse of pack_key.
inline std::uint64_t unpack_key(BlockKey k) {
  std::uint64_t t = (std::uint64_t(k) & 0xFFFu) | ((std::uint64_t(k) & 0xFFF000u) << 20);
  t = (t & 0x0000003F0000003Full) | ((t & 0x00000FC000000FC0ull) << 10);
  return (t & 0x0007000700070007ull) | ((t & 0x0038003800380038ull) << 5);
}

/// The key of the block after this tick's rule.
template <bool kRandom>
inline BlockKey next_key(const StepContext& c, BlockKey key, int x0, int y0, int z0) {
  if constexpr (kRandom) {
    const int s = int(block_random(c.seed, c.tick, x0, y0, z0) & 7u);
    return permute_key(c.result[permute_key(key, kKeySymmetry.forward[s])], kKeySymmetry.inverse[s]);
  } else {
    return c.result[key];
  }
}

/// The block's 8 bytes after this tick's (or sub-step's) rule: the result table's key for the
/// plain rules, motion::step_block with the motion model.
template <bool kRandom, bool kMotion>
inline std::uint64_t block_after(const StepContext& c, std::uint64_t v, int x0, int y0, int z0) {
  if constexpr (kMotion) {
    return motion::step_block(v, c.sub, x0, y0, z0, [&c](BlockKey k) { return c.transitions[k]; });
  } else {
    return unpack_key(next_key<kRandom>(c, pack_key(v), x0, y0, z0));
  }
}

}  // namespace granular::cpu_ops
