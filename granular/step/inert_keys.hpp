#pragma once
/// @file inert_keys.hpp
/// Inert keys: block states that no variant of the rule set can change. Sparse stepping puts a
/// brick to sleep only when every block it owns is inert, because "unchanged during the last cycle"
/// does not imply "unchanged under the next cycle's random draws" (docs/design/sparse-stepping.md).
///
/// The variants a rule set may pick for a block are listed by rule_variant_count / variant_key:
/// today the identity and, with RuleSet::random_symmetry, the 8 horizontal symmetries. A future
/// rule with other random choices (e.g. a per-block choice between two tables) must add its
/// variants here, so that a key is inert only if it is a fixed point under every one of them.

#include <cstdint>
#include <span>
#include <vector>

#include "granular/extend/block.hpp"

namespace granular {

/// Number of rule variants a block may be stepped under: 8 with random symmetry, else 1.
constexpr int rule_variant_count(bool random_symmetry) { return random_symmetry ? 8 : 1; }

/// The key of a block viewed under variant `v` (horizontal symmetry v: cell i moves to map[i]),
/// i.e. the key that is looked up in the result table when the block draws v.
constexpr BlockKey variant_key(BlockKey key, int v) {
  if (v == 0) return key;
  const auto map = horizontal_symmetry(v);
  BlockKey viewed = 0;
  for (int i = 0; i < 8; ++i) viewed |= ((key >> (3 * i)) & 7u) << (3 * map[i]);
  return viewed;
}

/// True when no variant changes a block of key `key`: `result(k)` (the key after the transition of
/// key k) maps every variant's view of it to itself.
template <class Result>
constexpr bool key_is_inert_by(BlockKey key, bool random_symmetry, Result&& result) {
  for (int v = 0; v < rule_variant_count(random_symmetry); ++v) {
    const BlockKey viewed = variant_key(key, v);
    if (result(viewed) != viewed) return false;
  }
  return true;
}

/// key_is_inert_by with a result table (per key, the key after the transition).
constexpr bool key_is_inert(BlockKey key, bool random_symmetry, const BlockKey* result) {
  return key_is_inert_by(key, random_symmetry, [result](BlockKey k) { return result[k]; });
}

/// Words of an inert-key bit table (one bit per key).
inline constexpr std::uint32_t kInertTableWords = kBlockKeyCount / 64;

/// The inert-key bit table of a result table: bit (k & 63) of word k >> 6 set when key k is inert.
std::vector<std::uint64_t> derive_inert_table(std::span<const BlockKey> result, bool random_symmetry, int threads);

/// The same table for the motion model's rest keys (motion::rest_key), from its transition table
/// `lut`: only keys of the codes void, obstacle and grain are ever asked about, 3^8 = 6561 of them,
/// so only their bits are derived (every other bit is 0).
std::vector<std::uint64_t> derive_rest_inert_table(std::span<const Transition> lut, bool random_symmetry);

/// Looks up key k in an inert-key bit table.
constexpr bool is_inert(const std::uint64_t* table, BlockKey key) { return (table[key >> 6] >> (key & 63u)) & 1u; }

}  // namespace granular
