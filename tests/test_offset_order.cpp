#include <doctest/doctest.h>

#include <set>

#include "granular/extend/block.hpp"
#include "granular/rule_presets.hpp"

using namespace granular;

TEST_CASE("block_offset without a random axis order is the paper's cycle") {
  for (std::uint64_t t = 0; t < 64; ++t) {
    const BlockOffset a = block_offset(t), b = block_offset(t, 12345, false);
    CHECK(a.x == b.x);
    CHECK(a.y == b.y);
    CHECK(a.z == b.z);
  }
}

TEST_CASE("a random axis order keeps every offset once per cycle, z every tick and x/y shared by tick pairs") {
  int swapped = 0;
  const int cycles = 512;
  for (std::uint64_t seed : {0ull, 1ull, 0xDEADBEEFull}) {
    for (std::uint64_t cycle = 0; cycle < std::uint64_t(cycles); ++cycle) {
      std::set<int> seen;
      for (std::uint64_t t = 8 * cycle; t < 8 * cycle + 8; ++t) {
        const BlockOffset o = block_offset(t, seed, true);
        CHECK(o.z == int(t & 1u));
        seen.insert(o.x | (o.y << 1) | (o.z << 2));
        if (t % 2 == 0) {
          const BlockOffset next = block_offset(t + 1, seed, true);
          CHECK(next.x == o.x);
          CHECK(next.y == o.y);
        }
      }
      CHECK(seen.size() == 8);
      swapped += cycle_swaps_axes(seed, 8 * cycle);
      CHECK(cycle_swaps_axes(seed, 8 * cycle) == cycle_swaps_axes(seed, 8 * cycle + 7));
    }
  }
  // Both orders occur, about equally often (3 x 512 fair draws: 768 +- 3 sigma = 768 +- 59).
  CHECK(swapped > 768 - 80);
  CHECK(swapped < 768 + 80);
}

TEST_CASE("presets: paper keeps the paper's cycle, isotropic draws symmetry and axis order, d4 the symmetry alone") {
  const auto paper = make_rule_set("paper"), iso = make_rule_set("isotropic"), d4 = make_rule_set("d4");
  CHECK_FALSE(paper->random_symmetry);
  CHECK_FALSE(paper->random_axis_order);
  CHECK(iso->random_symmetry);
  CHECK(iso->random_axis_order);
  CHECK(d4->random_symmetry);
  CHECK_FALSE(d4->random_axis_order);
  CHECK(rule_fingerprint(*iso) != rule_fingerprint(*d4));
}
