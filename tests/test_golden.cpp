/// @file test_golden.cpp
/// The CPU step against the pinned hashes of golden_table.hpp: every preset on several shipped
/// scenes and the scene of every material, sparse and dense. On a mismatch the plain per-block loop
/// reruns the case from the same initial grid, and the message says whether the fast step departs
/// from it (and where) or both agree, in which case the behaviour itself changed. The plain loop
/// itself reaches the pins of the scene of every material.

#include <doctest/doctest.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "golden_table.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "plain_divergence.hpp"
#include "plain_step.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::GoldenCase;
using granular::test::golden_def;
using granular::test::golden_entry;
using granular::test::hex64;
using granular::test::kGoldenCases;

namespace {

/// What went wrong with case `c` whose run gave `got`: the case, both hashes, the entry to paste
/// if the change is intended, and the plain loop's verdict on the same initial grid.
std::string golden_failure(const GoldenCase& c, const Grid& initial, bool sparse, std::uint64_t got) {
  std::string msg = "preset '" + std::string(c.preset) + "', scene '" + std::string(c.scene) + "' (N = " +
                    std::to_string(c.n) + ", " + to_string(initial.size()) + ", " + std::to_string(c.ticks) +
                    " ticks), CPU " + (sparse ? "sparse" : "dense") + ": got " + hex64(got) + ", expected " +
                    hex64(c.hash) + ". ";
  World world(golden_def(c, BackendKind::Cpu, sparse), initial);
  const granular::test::PlainTrajectory plain = granular::test::plain_trajectory(world, initial, c.ticks);
  const std::string departure = granular::test::departure_from_plain_loop(world, plain);
  if (!departure.empty()) return msg + "The fast step departs from the plain per-block loop: " + departure;
  return msg + "The fast step and the plain per-block loop agree after every tick (" +
         hex64(granular::test::plain_hash_after(plain, plain.after_tick.size() - 1)) +
         "), so the behaviour itself changed; if that is intended, pin " + golden_entry(c, got) +
         " in golden_table.hpp and give the reason in the commit.";
}

}  // namespace

TEST_CASE("golden: every preset has pinned hashes on at least three scenes") {
  std::map<std::string, int> scenes;
  for (const GoldenCase& c : kGoldenCases) ++scenes[std::string(c.preset)];
  for (const std::string& preset : rule_preset_names()) {
    CAPTURE(preset);
    CHECK(scenes[preset] >= 3);
  }
  CHECK(scenes.size() == rule_preset_names().size());  // no case of a preset that is gone
}

TEST_CASE("golden: the CPU step, sparse and dense, reaches the pinned hash of every preset on every scene") {
  std::string preset_alive;
  std::unique_ptr<World> keep_tables_alive;  // worlds of one process share the 64 MiB tables while one lives
  for (const GoldenCase& c : kGoldenCases) {
    const Grid initial = granular::test::golden_initial(c);
    if (preset_alive != c.preset) {
      preset_alive = std::string(c.preset);
      keep_tables_alive = std::make_unique<World>(golden_def(c, BackendKind::Cpu, true), Grid({8, 8, 8}));
    }
    for (const bool sparse : {true, false}) {
      World world(golden_def(c, BackendKind::Cpu, sparse), initial);
      world.step(c.ticks);
      const std::uint64_t got = world.hash();
      if (got != c.hash) FAIL_CHECK(golden_failure(c, initial, sparse, got));
      CHECK_MESSAGE(got != initial.hash(), "scene '" << std::string(c.scene) << "' does not change in " << c.ticks << " ticks");
    }
  }
}

TEST_CASE("golden: the plain per-block loop reaches the pinned hash of the scene of every material") {
  // The pins of the fluid scene were taken from the fast step where the plain loop agreed; this keeps
  // them anchored to the plain loop.
  int cases = 0;
  for (const GoldenCase& c : kGoldenCases) {
    if (c.scene != granular::test::kAllMaterialsScene) continue;
    ++cases;
    const Grid initial = granular::test::golden_initial(c);
    const MaterialCounts counts = initial.count();
    for (const Material m : {Material::Void, Material::Solid, Material::Granular, Material::Liquid, Material::Gas,
                             Material::Gravel, Material::State6, Material::State7})
      CHECK_MESSAGE(counts[to_cell(m)] > 0, "no " << material_name(m) << " in the scene of every material");
    const World world(golden_def(c, BackendKind::Cpu, false), initial);
    const granular::test::PlainTrajectory plain = granular::test::plain_trajectory(world, initial, c.ticks);
    const std::uint64_t got = granular::test::plain_hash_after(plain, plain.after_tick.size() - 1);
    CHECK_MESSAGE(got == c.hash, "preset '" << std::string(c.preset) << "': the plain loop gives " << hex64(got)
                                            << ", pinned " << hex64(c.hash));
  }
  CHECK(cases == 8);
}
