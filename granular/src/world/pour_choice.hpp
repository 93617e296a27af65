#pragma once
/// @file pour_choice.hpp
/// Which void cells World::pour fills: of the void cells in its sphere, the `amount` of the
/// smallest hash of (seed, tick, call, position), a spray that looks random yet is the same on
/// every backend and every run with the seed.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "granular/geometry.hpp"
#include "granular/grid.hpp"

namespace granular {

class RegionEdit;

/// A void cell pour may fill: its key, and its position packed as the key's hash takes it.
struct PourCandidate {
  std::uint64_t key = 0;       ///< pour_key(salt, position): the smaller, the sooner the cell is filled
  std::uint64_t position = 0;  ///< pack_position(p)
};

/// A grid position as one word: x, y and z (each below 2^21; kMaxGridExtent is less) in bits 0, 21
/// and 42 up.
constexpr std::uint64_t pack_position(int x, int y, int z) {
  return std::uint64_t(x) | std::uint64_t(y) << 21 | std::uint64_t(z) << 42;
}

/// The position pack_position packed.
constexpr Int3 unpack_position(std::uint64_t p) {
  constexpr std::uint64_t mask = (std::uint64_t(1) << 21) - 1;
  return {int(p & mask), int((p >> 21) & mask), int(p >> 42)};
}

/// The salt of one pour: a mix of the world's seed, its tick and the tool calls before it.
constexpr std::uint64_t pour_salt(std::uint64_t seed, std::uint64_t tick, std::uint64_t tool_calls) {
  return mix64(seed ^ mix64(tick * 0x9E3779B97F4A7C15ull + tool_calls));
}

/// The key that orders a pour's void cells: for one salt a bijection of the packed position, so no
/// two cells share one.
constexpr std::uint64_t pour_key(std::uint64_t salt, std::uint64_t position) { return mix64(salt ^ position); }

/// Moves the `keep` candidates of the smallest keys (which are distinct) to the front of
/// `candidates`, in no particular order, and returns them: all of them when there are no more.
std::span<PourCandidate> keep_smallest(std::span<PourCandidate> candidates, std::size_t keep);

/// The choice of one pour's cells, in a buffer reused from pour to pour.
class PourChoice {
 public:
  /// The void cells of `edit`'s region whose centres lie in `sphere`, of the `amount` smallest
  /// pour_key(salt, position) (all of them when there are no more), in no particular order; valid
  /// until the next call.
  /// The sphere and the positions are in the coordinates of the edit's spheres (RegionEdit::origin).
  std::span<const PourCandidate> choose(const RegionEdit& edit, const Sphere& sphere, std::uint64_t salt,
                                        std::size_t amount);
  /// Frees buffers a large sphere made large (trim_scratch).
  void trim();

 private:
  /// One row's cells in the sphere: x in [first, last) of row (y, z).
  struct Run {
    int y, z, first, last;
  };
  // Writes the void cells of the runs whose keys lie below `limit` to candidates_; returns how many.
  std::size_t gather(const RegionEdit& edit, std::uint64_t salt, std::uint64_t limit);

  std::vector<Run> runs_;                  ///< the sphere's rows (for_each_run_in_sphere)
  std::vector<PourCandidate> candidates_;  ///< room for a candidate per cell of the sphere
};

}  // namespace granular
