/// @file test_momentum.cpp
/// The momentum lever (MotionParams::momentum, preset inertial-24-momentum; granular/step/momentum.hpp
/// and the fluid pass's momentum stage): a burst dam's front runs much farther than under pressure
/// alone, connected vessels still level, sparse = dense on any thread count with the side plane in the
/// hash, every material is conserved, the velocities die out so a levelled U-tube sleeps, and the rule
/// set checks that the lever has pressure under it; snapshots hold the side plane and a world made
/// from one continues bit-identically. (The plain loop implements the lever independently and the
/// golden pins hold its behaviour: test_plain_step.cpp, test_golden.cpp.)

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdint>
#include <vector>

#include "granular/errors.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "reference/material_scenes.hpp"
#include "quick_u_tube.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::test_def;
using granular::test::with_sparse;
using UTube = granular::test::QuickUTube;

namespace {

/// The accuracy suite's quick dam break at H0 = 16 (dam_break_test.cpp): a liquid column 16 high and
/// 32 long at the closed end of a dry channel 8 wide, on a floor of solid.
struct Dam {
  static constexpr int kHead = 16, kColumn = 2 * kHead, kWidth = 8;
  static Int3 size() { return {kColumn + 2 * kHead + kHead / 2 + 8, kWidth, 1 + kHead + 4}; }
  static Grid build() {
    const Int3 s = size();
    Grid g(s);
    g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
    g.fill(Box{{0, 0, 1}, {kColumn, s.y, 1 + kHead}}, Material::Liquid);
    return g;
  }
  /// The front's travel past the dam: the end of the run of wet columns on the floor (the suite's front).
  static int travel(const World& w) {
    const Int3 s = size();
    const std::vector<std::uint8_t> cells = w.read_region(Box{{0, 0, 1}, {s.x, s.y, 2}});
    for (int x = 0; x < s.x; ++x) {
      bool wet = false;
      for (int y = 0; y < s.y && !wet; ++y) wet = cells[std::size_t(x) + std::size_t(s.x) * std::size_t(y)] == to_cell(Material::Liquid);
      if (!wet) return std::max(0, x - kColumn);
    }
    return s.x - kColumn;
  }
};

}  // namespace

TEST_CASE("momentum: a burst dam's front reaches 2 H0 within 24 ticks, as it does not under pressure alone") {
  // Ritter's front covers 2 H0 = 32 cells in 2.8 ticks; under pressure alone it takes about 50.
  const Grid initial = Dam::build();
  World moving(test_def(Dam::size(), "inertial-24-momentum", 2, 1), initial);
  World pressed(test_def(Dam::size(), "inertial-24-pressure", 2, 1), initial);
  const MaterialCounts before = moving.count();
  int ran = 0, crept = 0;  // the farthest travel of each front
  for (int t = 0; t < 24; ++t) {
    moving.step(1);
    pressed.step(1);
    ran = std::max(ran, Dam::travel(moving));
    crept = std::max(crept, Dam::travel(pressed));
  }
  CAPTURE(ran);
  CAPTURE(crept);
  CHECK(ran >= 2 * Dam::kHead);
  CHECK(crept < 2 * Dam::kHead);
  CHECK(moving.count() == before);
}

TEST_CASE("momentum: the legs of a U-tube still level within a cell, and the tube comes to rest and sleeps") {
  const Grid g = UTube::build();
  World w(test_def(g.size(), "inertial-24-momentum", 2, 1), g);
  w.step(480);
  const double left = UTube::level(w, 0), right = UTube::level(w, UTube::kRight);
  CAPTURE(left);
  CAPTURE(right);
  CHECK(std::abs(left - right) <= 1.0);
  w.step(1);
  CHECK(w.activity().active_bricks == 0);  // no velocity is left in the level tube
}

TEST_CASE("momentum: sparse = dense on 1 and 2 threads every few ticks, and every material is conserved") {
  struct Scene {
    Grid grid;
    int ticks;
  };
  Grid mixed = granular::test::all_materials_scene({33, 20, 24}, 0x5EED);
  std::vector<Scene> scenes;
  scenes.push_back({Dam::build(), 300});
  scenes.push_back({std::move(mixed), 200});
  for (const Scene& scene : scenes) {
    const Int3 size = scene.grid.size();
    CAPTURE(size.x);
    std::vector<std::vector<std::uint64_t>> runs;
    MaterialCounts end{};
    for (const int threads : {1, 2})
      for (const bool sparse : {false, true}) {
        World w(with_sparse(test_def(size, "inertial-24-momentum", threads, 5), sparse), scene.grid);
        std::vector<std::uint64_t> hashes;
        for (int t = 0; t < scene.ticks; t += 7) {
          w.step(7);
          hashes.push_back(w.hash());
        }
        runs.push_back(hashes);
        end = w.count();
      }
    for (std::size_t i = 1; i < runs.size(); ++i) CHECK(runs[i] == runs[0]);
    CHECK(end == scene.grid.count());
  }
}

TEST_CASE("momentum: the lever needs pressure, and the error names the field") {
  RuleSet r = preset("inertial-24-momentum");
  r.motion.pressure = false;
  CHECK_THROWS_WITH_AS(validate_rule_set(r), doctest::Contains("RuleSet::motion.momentum = true with motion.pressure = false"),
                       RuleError);
}

TEST_CASE("momentum: a snapshot holds the velocities, in memory and in a version 4 file, and a world made from it continues bit-identically") {
  const Grid initial = Dam::build();
  const WorldDef def = test_def(Dam::size(), "inertial-24-momentum", 2, 3);
  World running(def, initial);
  running.step(6);  // mid-burst: liquids run with velocities
  const WorldSnapshot snap = running.capture();
  REQUIRE(snap.side.size() == snap.cells.size());
  CHECK(snap.hash() == running.hash());
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "granular_test_momentum.gsnap";
  save_snapshot(snap, path);
  const std::vector<std::uint8_t> bytes = encode_snapshot(snap);
  CHECK(bytes[4] == kSideSnapshotVersion);
  const WorldSnapshot loaded = load_snapshot(path);
  std::filesystem::remove(path);
  CHECK(loaded.side == snap.side);
  World from_file(def, loaded);
  World restored(def, initial);
  restored.step(40);  // a different state, velocities included, which restore replaces
  restored.restore(snap);
  CHECK(from_file.hash() == running.hash());
  CHECK(restored.hash() == running.hash());
  for (int t = 0; t < 30; ++t) {
    running.step(1);
    from_file.step(1);
    restored.step(1);
  }
  CHECK(from_file.hash() == running.hash());
  CHECK(restored.hash() == running.hash());
  // Without its velocities the same cells continue differently: the side plane is state.
  WorldSnapshot stripped = snap;
  stripped.side.clear();
  World forgetful(def, stripped);
  World remembering(def, snap);
  forgetful.step(10);
  remembering.step(10);
  CHECK(forgetful.hash() != remembering.hash());
}

TEST_CASE("momentum: a snapshot's side plane is checked, and each error names the field, the cell and the value") {
  const Grid initial = Dam::build();
  const WorldDef def = test_def(Dam::size(), "inertial-24-momentum", 2, 3);
  World running(def, initial);
  running.step(6);
  const WorldSnapshot snap = running.capture();
  REQUIRE(!snap.side.empty());
  WorldSnapshot short_side = snap;
  short_side.side.resize(10);
  CHECK_THROWS_WITH_AS(World(def, short_side), doctest::Contains("WorldSnapshot::side holds 10 bytes"), InvalidArgument);
  WorldSnapshot on_solid = snap;
  on_solid.side[0] = 0x01;  // cell (0, 0, 0) is the floor
  CHECK_THROWS_WITH_AS(World(def, on_solid), doctest::Contains("WorldSnapshot::side of cell (0, 0, 0) is 1 but the cell holds 1, not a liquid"),
                       InvalidArgument);
  WorldSnapshot minus_eight = snap;
  const std::size_t liquid = std::size_t(Dam::size().x) * std::size_t(Dam::size().y);  // cell (0, 0, 1)
  REQUIRE(minus_eight.cells[liquid] == to_cell(Material::Liquid));
  minus_eight.side[liquid] = 0x08;
  CHECK_THROWS_WITH_AS(running.restore(minus_eight), doctest::Contains("a component of -8"), InvalidArgument);
  WorldSnapshot other_rules = snap;
  other_rules.rules = "inertial-24-pressure";
  other_rules.rule_fingerprint = rule_fingerprint(preset("inertial-24-pressure"));
  CHECK_THROWS_WITH_AS(World(test_def(Dam::size(), "inertial-24-pressure", 2, 3), other_rules),
                       doctest::Contains("has no side plane (RuleSet::motion.momentum = false)"), InvalidArgument);
}

TEST_CASE("momentum: a cell a tool changes starts at rest, and the velocities of the cells it leaves stay") {
  const Grid initial = Dam::build();
  World w(test_def(Dam::size(), "inertial-24-momentum", 2, 3), initial);
  w.step(6);
  const WorldSnapshot before = w.capture();
  REQUIRE(!before.side.empty());
  // Paint gas over the channel beyond the column: the liquid there becomes gas, at rest.
  const Box box{{Dam::kColumn, 0, 1}, {Dam::size().x, Dam::size().y, Dam::size().z}};
  w.paint(box, Material::Gas);
  const WorldSnapshot after = w.capture();
  REQUIRE(after.side.size() == before.side.size());
  const Int3 s = Dam::size();
  int kept = 0, cleared = 0;
  for (int z = 0; z < s.z; ++z)
    for (int y = 0; y < s.y; ++y)
      for (int x = 0; x < s.x; ++x) {
        const std::size_t i = std::size_t(x) + std::size_t(s.x) * (std::size_t(y) + std::size_t(s.y) * std::size_t(z));
        const bool inside = x >= box.min.x && z >= box.min.z;
        if (before.side[i] == 0) continue;
        if (inside && before.cells[i] != after.cells[i]) {
          CHECK(after.side[i] == 0);
          ++cleared;
        } else if (!inside) {
          CHECK(after.side[i] == before.side[i]);
          ++kept;
        }
      }
  CHECK(cleared > 0);
  CHECK(kept > 0);
}
