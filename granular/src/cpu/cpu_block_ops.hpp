#pragma once
/// @file cpu_block_ops.hpp
/// The CPU's Platform policy of the one block step (step/block_step.hpp) and its cell-row loads and
/// stores, shared by the dense kernel (cpu_step.cpp) and the sparse one (cpu_sparse_step.cpp).

#include <array>
#include <cstdint>
#include <cstring>

#include "cpu/cpu_step.hpp"
#include "granular/extend/block.hpp"
#include "step/block_step.hpp"

namespace granular::cpu_ops {

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

/// The CPU's Platform: plain loads, symmetries through the byte tables.
struct HostPlatform {
  /// Reads a table entry.
  template <class T>
  static T load(const T* p) {
    return *p;
  }
  /// The key as seen under symmetry s.
  static BlockKey view(BlockKey key, int s) { return permute_key(key, kKeySymmetry.forward[s]); }
  /// The inverse of view.
  static BlockKey unview(BlockKey key, int s) { return permute_key(key, kKeySymmetry.inverse[s]); }
};

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

/// Calls fn(rule) with the Rule of the context's (sub-)step.
template <class Fn>
inline void with_host_rule(const StepContext& c, Fn&& fn) {
  with_rule<HostPlatform>(c.rules, c.tick, c.substep, fn);
}

}  // namespace granular::cpu_ops
