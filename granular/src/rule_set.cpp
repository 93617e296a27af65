#include "granular/rule_set.hpp"

#include "granular/grid.hpp"

namespace granular {

std::uint64_t rule_fingerprint(const RuleSet& rules) {
  std::uint64_t h = 0x72756C6573657431ull;
  for (char c : rules.name) h = mix64(h ^ std::uint8_t(c));
  h = mix64(h ^ rules.version);
  h = mix64(h ^ (rules.random_symmetry ? 1u : 0u));
  if (rules.random_axis_order) h = mix64(h ^ 0x617865736F726465ull);
  if (rules.motion.enabled())
    h = mix64(h ^ 0x6D6F74696F6E0000ull ^ std::uint64_t(rules.motion.substeps) ^
              (std::uint64_t(rules.motion.roll_chance) << 8) ^ (std::uint64_t(rules.motion.topple_gain) << 20) ^
              (std::uint64_t(rules.motion.roll_cost) << 32));
  if (!rules.transition) return h;
  // Every block over the three simulated states.
  for (std::uint32_t n = 0; n < 6561; ++n) {
    BlockCells cells{};
    std::uint32_t v = n;
    for (int i = 0; i < 8; ++i, v /= 3) cells[i] = std::uint8_t(v % 3);
    h = mix64(h ^ rules.transition(cells)) + n;
  }
  // A pseudo-random sample over all 8 states.
  for (std::uint64_t n = 0; n < 4096; ++n) {
    const BlockKey key = BlockKey(mix64(n * 0x9E3779B97F4A7C15ull) & (kBlockKeyCount - 1));
    h = mix64(h ^ rules.transition(decode_key(key))) + key;
  }
  return h;
}

}  // namespace granular
