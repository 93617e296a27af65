#pragma once
/// @file test_support.hpp
/// The shared test context: world definitions that use the build tree's table cache, and random
/// scene generators used by the conservation and determinism tests.

#include <doctest/doctest.h>

#include <cstdint>
#include <initializer_list>
#include <random>
#include <string>
#include <string_view>

#include "granular/grid.hpp"
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
    FAIL("wrong exception type, message: " << e.what());
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

}  // namespace granular::test
