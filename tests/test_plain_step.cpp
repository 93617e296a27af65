/// @file test_plain_step.cpp
/// The fast CPU step against the plain per-block loop (tests/reference/plain_step.hpp) for every
/// preset: World on the CPU backend, sparse and dense, 1 and 2 threads, compared with the plain
/// loop after every tick of random scenes holding all 8 states, on odd and even grid sizes; and
/// the plain loop on several threads (as the benchmark runs it) against itself on one.

#include <doctest/doctest.h>

#include <cstdint>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "granular/grid.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "plain_divergence.hpp"
#include "plain_step.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::departure_from_plain_loop;
using granular::test::plain_trajectory;
using granular::test::test_def;

namespace {

/// Ticks each scene runs: three 8-tick offset cycles.
constexpr int kTicks = 24;

/// A random scene holding every one of the 8 states: below half height a rough ground of grains,
/// void, solid and a few of each other state; above it grains scattered in void, which fall, land,
/// topple and (with the motion model) accelerate and roll. Every grain starts at rest (no motion bits).
Grid mixed_scene(Int3 size, std::uint64_t seed) {
  Grid g(size);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pct(0, 99);
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const int p = pct(rng);
        Material m = Material::Void;
        if (z < size.z / 2) {
          if (p < 35) m = Material::Granular;
          else if (p < 45) m = Material::Solid;
          else if (p < 60) m = Material(3 + (p - 45) / 3);  // liquid, gas, states 5..7: 3% each
        } else if (p < 25) {
          m = Material::Granular;
        }
        g.set({x, y, z}, m);
      }
  return g;
}

}  // namespace

TEST_CASE("plain step: World's hash is the hash of its cell bytes, as the plain loop's grids are hashed") {
  const Grid initial = mixed_scene({17, 12, 9}, 3);
  const World world(test_def(initial.size(), "paper", 1, 3), initial);
  CHECK(world.hash() == hash_cells(initial.size(), initial.cells()));
  CHECK(world.hash() == initial.hash());
}

TEST_CASE("plain step: World on the CPU, sparse and dense, 1 and 2 threads, equals the plain loop after every tick of every preset") {
  const Int3 sizes[] = {{17, 12, 9}, {33, 20, 16}, {40, 40, 24}};
  const std::uint64_t seeds[] = {1, 0x5EED0002, 77};
  for (const std::string& preset : rule_preset_names()) {
    // Worlds of one process share the 64 MiB tables while one of them lives.
    const World keep_tables_alive(test_def({8, 8, 8}, preset.c_str(), 1), Grid({8, 8, 8}));
    for (std::size_t k = 0; k < std::size(sizes); ++k) {
      const Int3 size = sizes[k];
      const std::uint64_t seed = seeds[k];
      const Grid initial = mixed_scene(size, seed ^ 0xC0FFEE);
      const MaterialCounts counts = initial.count();
      for (int m = 0; m < kMaterialCount; ++m) REQUIRE_MESSAGE(counts[std::size_t(m)] > 0, "state " << m << " missing");
      const World first(test_def(size, preset.c_str(), 1, seed), initial);
      const granular::test::PlainTrajectory plain = plain_trajectory(first, initial, kTicks);
      REQUIRE(plain.after_tick.back() != std::vector<std::uint8_t>(initial.cells().begin(), initial.cells().end()));
      // The plain loop's own thread split (the benchmark's) changes nothing.
      std::vector<std::uint8_t> threaded(initial.cells().begin(), initial.cells().end());
      reference::plain_run(threaded, size, reference::plain_rules(first.rules(), first.lut(), seed), 0, kTicks, 3);
      const std::string split = granular::test::first_differing_cell(size, plain.after_tick.back(), threaded,
                                                                     "plain loop on 1 thread", "on 3 threads");
      CHECK_MESSAGE(split.empty(), "preset " << preset << ", " << to_string(size) << ": " << split);
      for (const bool sparse : {true, false})
        for (const int threads : {1, 2}) {
          WorldDef def = test_def(size, preset.c_str(), threads, seed);
          def.sparse = sparse;
          World world(def, initial);
          const std::string departure = departure_from_plain_loop(world, plain);
          CHECK_MESSAGE(departure.empty(), "preset " << preset << ", " << to_string(size) << ", seed " << seed << ", "
                                                     << std::string(sparse ? "sparse" : "dense") << ", " << threads
                                                     << " thread(s): " << departure);
        }
    }
  }
}
