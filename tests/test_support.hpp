#pragma once
/// @file test_support.hpp
/// The shared test context: world definitions that use the build tree's table cache, and random
/// scene generators used by the conservation and determinism tests.

#include <doctest/doctest.h>

#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <string_view>

#include "granular/grid.hpp"
#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"

namespace granular::test {

/// A WorldDef for tests: the given size, rules and threads; the table cache from the environment.
inline WorldDef test_def(Int3 size, const char* rules = "paper", int threads = 2, std::uint64_t seed = 1) {
  WorldDef def;
  def.size = size;
  def.rules = rules;
  def.threads = threads;
  def.seed = seed;
  def.backend = BackendKind::Cpu;
  return def;
}

/// `def` with sparse stepping on or off.
inline WorldDef with_sparse(WorldDef def, bool sparse) {
  def.sparse = sparse;
  return def;
}

/// `def` as a DistributedWorld takes it: a preset with MotionParams::trains (which a distributed world
/// refuses) runs as its own rule set without them, every other lever kept.
inline WorldDef without_trains(WorldDef def) {
  if (def.rule_set == nullptr && preset(def.rules).motion.trains) {
    auto rules = std::make_shared<RuleSet>(preset(def.rules));
    rules->motion.trains = false;
    def.rule_set = std::move(rules);
  }
  return def;
}

/// A random grid: each cell void, solid or granular with the given probabilities (percent).
inline Grid random_grid(Int3 size, std::uint64_t seed, int solid_percent = 10, int granular_percent = 35) {
  Grid g(size);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pct(0, 99);
  for (auto& c : g.cells()) {
    const int p = pct(rng);
    c = p < solid_percent ? to_cell(Material::Solid)
        : p < solid_percent + granular_percent ? to_cell(Material::Granular)
                                               : to_cell(Material::Void);
  }
  return g;
}

/// A random grid over all 8 states (reserved ones included), uniformly.
inline Grid random_grid_all_states(Int3 size, std::uint64_t seed) {
  Grid g(size);
  std::mt19937_64 rng(seed);
  for (auto& c : g.cells()) c = std::uint8_t(rng() % kMaterialCount);
  return g;
}

/// A random grid with every material moving: half void, some solid and the two static states of a
/// game's own, the rest sand, water, gas and gravel.
inline Grid mixed_material_grid(Int3 size, std::uint64_t seed) {
  Grid g(size);
  std::mt19937_64 rng(seed);
  for (std::uint8_t& c : g.cells()) {
    const int p = int(rng() % 100);
    c = p < 50 ? 0 : p < 58 ? 1 : p < 60 ? std::uint8_t(6 + rng() % 2) : std::uint8_t(2 + rng() % 4);
  }
  return g;
}

/// A random size with each extent in [lo, hi] (odd ones included).
inline Int3 random_size(std::mt19937_64& rng, int lo, int hi) {
  std::uniform_int_distribution<int> d(lo, hi);
  return {d(rng), d(rng), d(rng)};
}

/// Runs `f`, requires that it throws exactly an `E` (a FAIL otherwise), and returns the message.
template <class E, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    FAIL("wrong exception type, message: " << std::string(e.what()));
    return {};
  }
  FAIL("no exception was thrown");
  return {};
}

/// Checks that `msg` contains every one of `parts`.
inline void check_has(const std::string& msg, std::initializer_list<std::string_view> parts) {
  for (std::string_view p : parts)
    CHECK_MESSAGE(msg.find(p) != std::string::npos, "expected '" << p << "' in: " << msg);
}

/// A cell byte for messages: "0x92 (granular, motion level 2, phase 1)".
inline std::string describe_cell(std::uint8_t byte) {
  char hex[8];
  std::snprintf(hex, sizeof hex, "0x%02x", unsigned(byte));
  return std::string(hex) + " (" + std::string(material_name(Material(cell_material(byte)))) + ", motion level " +
         std::to_string(cell_motion(byte)) + ", phase " + ((byte & kMotionPhaseBit) ? "1" : "0") + ")";
}

/// "" when `expected` and `actual`, the cells of two grids of extent `size` (x fastest), are equal;
/// else a message naming the first differing cell (x, y, z) in memory order and both of its bytes
/// (describe_cell), each side called by its name.
inline std::string first_differing_cell(Int3 size, std::span<const std::uint8_t> expected,
                                        std::span<const std::uint8_t> actual, std::string_view expected_name = "expected",
                                        std::string_view actual_name = "actual") {
  const std::size_t cells = std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z);
  if (expected.size() != cells || actual.size() != cells)
    return "cannot compare: " + std::string(expected_name) + " holds " + std::to_string(expected.size()) + " cells, " +
           std::string(actual_name) + " " + std::to_string(actual.size()) + ", a " + to_string(size) + " grid " +
           std::to_string(cells);
  for (std::size_t i = 0; i < cells; ++i) {
    if (expected[i] == actual[i]) continue;
    const std::size_t x = i % std::size_t(size.x), y = (i / std::size_t(size.x)) % std::size_t(size.y),
                      z = i / (std::size_t(size.x) * std::size_t(size.y));
    return "first differing cell (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
           ") of the " + to_string(size) + " grid: " + std::string(expected_name) + " " + describe_cell(expected[i]) +
           ", " + std::string(actual_name) + " " + describe_cell(actual[i]);
  }
  return {};
}

}  // namespace granular::test
