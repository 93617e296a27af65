#pragma once
/// @file grid.hpp
/// A dense voxel grid on the host: one byte per cell holding a Material value, x fastest, then y,
/// then z (up). Used for scenes, import/export and reading back a world's state.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "granular/geometry.hpp"
#include "granular/material.hpp"

namespace granular {

/// Largest extent allowed along one axis.
inline constexpr int kMaxGridExtent = 65536;

/// Throws InvalidArgument naming `what` when `size` has a zero, negative or over-large extent.
void check_grid_extents(Int3 size, const std::string& what);

/// check_grid_extents, then throws OutOfMemory when `bytes_per_cell * cells + extra_bytes` exceeds
/// the memory this process may still allocate (available_memory(): MemAvailable, the cgroup limit,
/// RLIMIT_AS and RLIMIT_DATA); the message gives the size, the bytes needed and the limit that
/// decides. `what` names the caller's field
/// (e.g. "WorldDef::size", "scene 'bowl' size").
void check_grid_size(Int3 size, const std::string& what, double bytes_per_cell = 1.0, double extra_bytes = 0);

/// "NXxNYxNZ" for messages.
std::string to_string(Int3 size);

/// Dense host-side grid of cells.
class Grid {
 public:
  /// An empty 0x0x0 grid (only useful as a placeholder to assign into).
  Grid() = default;
  /// A grid of `size` void cells. Throws InvalidArgument / OutOfMemory (see check_grid_size); a
  /// failed allocation is an OutOfMemory naming the size and the bytes.
  explicit Grid(Int3 size);
  /// A copy of `other`; a failed allocation is an OutOfMemory naming the size and the bytes.
  Grid(const Grid& other);
  /// Copies `other` (OutOfMemory as the copy constructor; this grid is unchanged then).
  Grid& operator=(const Grid& other);
  /// Takes the cells of `other`, which becomes an empty 0x0x0 grid.
  Grid(Grid&& other) noexcept;
  /// Takes the cells of `other`, which becomes an empty 0x0x0 grid.
  Grid& operator=(Grid&& other) noexcept;

  /// Extent per axis.
  Int3 size() const { return size_; }
  /// Total number of cells.
  std::int64_t cell_count() const { return std::int64_t(cells_.size()); }
  /// The box [0, size).
  Box bounds() const { return {{0, 0, 0}, size_}; }
  /// True when `p` lies inside the grid.
  bool contains(Int3 p) const {
    return p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x < size_.x && p.y < size_.y && p.z < size_.z;
  }
  /// Linear index of an in-grid cell (x fastest).
  std::size_t index(Int3 p) const {
    return std::size_t(p.x) + std::size_t(size_.x) * (std::size_t(p.y) + std::size_t(size_.y) * std::size_t(p.z));
  }
  /// Material at an in-grid cell (unchecked).
  Material at(Int3 p) const { return Material(cells_[index(p)]); }
  /// Sets an in-grid cell (unchecked).
  void set(Int3 p, Material m) { cells_[index(p)] = to_cell(m); }

  /// Raw cell bytes.
  std::span<std::uint8_t> cells() { return cells_; }
  /// Raw cell bytes.
  std::span<const std::uint8_t> cells() const { return cells_; }

  /// Sets every cell of `box` (clipped to the grid) to `m`.
  void fill(const Box& box, Material m);
  /// Cells per material.
  MaterialCounts count() const;
  /// 64-bit hash of size and content (see hash_cells).
  std::uint64_t hash() const;

 private:
  Int3 size_{0, 0, 0};
  std::vector<std::uint8_t> cells_;
};

/// The grid hash: equal for equal size and content on every backend and thread count.
/// Defined as mix(size) + sum over 8-byte little-endian words w_i (tail zero-padded) of
/// mix(w_i + (i+1) * 0x9E3779B97F4A7C15), finalised by mix; mix is the splitmix64 finaliser.
/// The sum makes it order-independent, so GPUs and threads can reduce it in any order.
std::uint64_t hash_cells(Int3 size, std::span<const std::uint8_t> cells);

/// What a side plane (MotionParams::momentum: one byte per cell, x fastest) adds to the sum of
/// hash_words partials of its grid: 0 when it holds only zeros (a world at rest hashes as its
/// cells), else a mix of its own hash_words sum. Backends and WorldSnapshot::hash add it alike.
std::uint64_t side_hash_term(std::span<const std::uint8_t> side);

/// What a face plane (MotionParams::shallow: 4 int32 per column) adds to the sum of hash_words
/// partials of its grid: 0 when it holds only zeros (or is empty), else a mix of a sum over its
/// values v_i of mix(uint32(v_i) + (i+1) * 0x9E3779B97F4A7C15). Backends and WorldSnapshot::hash add
/// it alike.
std::uint64_t faces_hash_term(std::span<const std::int32_t> faces);

/// Partial hash of a word range [first_word, first_word + count) of `cells` (the summand of
/// hash_cells), for backends that reduce in parallel; combine with finish_hash.
std::uint64_t hash_words(std::span<const std::uint8_t> cells, std::size_t first_word, std::size_t word_count);

/// The summand of hash_cells for the words numbered first_word, first_word + 1, ... held in `bytes`,
/// 8 bytes per word (a short last word counts its missing bytes as 0): a part of a grid held
/// elsewhere (a DistributedWorld's slab) sums its own words.
std::uint64_t hash_words_from(std::span<const std::uint8_t> bytes, std::size_t first_word);

/// Finalises a sum of hash_words partials for a grid of `size`.
std::uint64_t finish_hash(Int3 size, std::uint64_t partial_sum);

/// The splitmix64 finaliser: a strong 64-bit bijective mix.
constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// side_hash_term of a side plane that holds a non-zero byte, from its hash_words sum `word_sum`:
/// what a backend that reduces the plane in parallel adds.
constexpr std::uint64_t side_hash_of_sum(std::uint64_t word_sum) {
  return mix64(word_sum ^ 0x73696465706C616Eull);  // "sideplan"
}

}  // namespace granular
