#include "world/pour_choice.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <utility>

#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "world/region_edit.hpp"
#include "cpu/scratch_buffer.hpp"
#include "world/sphere_runs.hpp"

namespace granular {

namespace {

/// The largest key: no limit.
constexpr std::uint64_t kNoLimit = ~std::uint64_t(0);

/// A key below which, of `count` hash keys spread evenly over 64 bits, about keep + 4 sqrt(keep) + 16
/// lie, so fewer than `keep` only by rare chance; kNoLimit when that is most of them.
std::uint64_t key_limit(std::size_t keep, std::size_t count) {
  const double wanted = double(keep) + 4.0 * std::sqrt(double(keep)) + 16.0;
  if (!(wanted < 0.5 * double(count))) return kNoLimit;
  return std::uint64_t(wanted / double(count) * 0x1p64);
}

/// Moves the candidates `in` holds for to the front of `pool` (a Lomuto partition that swaps every
/// candidate and counts those it holds for, without a branch, which random keys would mispredict);
/// returns how many.
template <class In>
std::size_t partition_front(std::span<PourCandidate> pool, In&& in) {
  std::size_t front = 0;
  for (PourCandidate& c : pool) {
    const bool held = in(c);
    std::swap(pool[front], c);
    front += held ? 1 : 0;
  }
  return front;
}

}  // namespace

std::span<PourCandidate> keep_smallest(std::span<PourCandidate> candidates, std::size_t keep) {
  if (candidates.size() <= keep) return candidates;
  // By the 8 bits below the largest key's top bit: the buckets below the one where the count
  // reaches `keep`, and of that bucket the smallest keys.
  std::uint64_t largest = 0;
  for (const PourCandidate& c : candidates) largest = std::max(largest, c.key);
  const int shift = std::max(0, int(std::bit_width(largest)) - 8);
  std::array<std::size_t, 256> count{};
  for (const PourCandidate& c : candidates) ++count[c.key >> shift];
  std::uint64_t bucket = 0;
  std::size_t below = 0;
  while (below + count[bucket] < keep) below += count[bucket++];
  partition_front(candidates, [&](const PourCandidate& c) { return (c.key >> shift) < bucket; });
  partition_front(candidates.subspan(below), [&](const PourCandidate& c) { return (c.key >> shift) == bucket; });
  std::nth_element(candidates.begin() + std::ptrdiff_t(below), candidates.begin() + std::ptrdiff_t(keep),
                   candidates.begin() + std::ptrdiff_t(below + count[bucket]),
                   [](const PourCandidate& a, const PourCandidate& b) { return a.key < b.key; });
  return candidates.first(keep);
}

std::size_t PourChoice::gather(const RegionEdit& edit, std::uint64_t salt, std::uint64_t limit) {
  const Int3 origin = edit.origin();
  const std::uint8_t* const cells = edit.cells().data();
  PourCandidate* const out = candidates_.data();
  std::size_t found = 0;
  // Every cell is written and kept when void with a key below the limit, without a branch (which
  // a sphere of void and grains, and the random keys, would mispredict).
  for (const Run& run : runs_) {
    const RegionEdit::Row row = edit.row(run.y, run.z);
    const std::uint64_t row_position = pack_position(origin.x, run.y + origin.y, run.z + origin.z);
    for (int x = run.first; x < run.last; ++x) {
      const std::uint64_t position = row_position + std::uint64_t(x);
      const std::uint64_t key = pour_key(salt, position);
      out[found] = {key, position};
      found += cell_material(cells[row.cell(x)]) == to_cell(Material::Void) && key < limit ? 1 : 0;
    }
  }
  return found;
}

std::span<const PourCandidate> PourChoice::choose(const RegionEdit& edit, const Sphere& sphere, std::uint64_t salt,
                                                  std::size_t amount) {
  runs_.clear();
  std::size_t in_sphere = 0;
  for_each_run_in_sphere(edit.region(), sphere, [&](int y, int z, int first, int last) {
    runs_.push_back({y, z, first, last});
    in_sphere += std::size_t(last - first);
  }, edit.origin());
  if (candidates_.size() < in_sphere) candidates_.resize(in_sphere);
  // First the void cells of keys below the limit for as many keys as the sphere holds cells: when
  // at least `amount` are, the `amount` smallest keys are among them (every key at or above the
  // limit is larger than each of those). Fewer (a sphere partly full, or by chance): all the void
  // cells.
  const std::uint64_t limit = key_limit(amount, in_sphere);
  std::size_t found = gather(edit, salt, limit);
  if (found < amount && limit != kNoLimit) found = gather(edit, salt, kNoLimit);
  return keep_smallest({candidates_.data(), found}, amount);
}

void PourChoice::trim() {
  trim_scratch(runs_);
  trim_scratch(candidates_);
}

}  // namespace granular
