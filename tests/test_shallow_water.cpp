/// @file test_shallow_water.cpp
/// The shallow-water lever (MotionParams::shallow, preset inertial-24-shallow;
/// granular/step/shallow_water.hpp): a burst dam runs out as a body and levels, where the default
/// rules leave a slope; a U-tube's legs level through the pipe under their wall and come to rest;
/// water runs over the top of a pipe; a sealed cavity stays still; every material is
/// conserved; sparse = dense on any thread count with the
/// face plane in the hash; the pool comes to rest and then costs nothing; a level pool with a partly
/// filled top layer never starts; snapshots (format version 5) hold the face plane and a world made
/// from one continues bit-identically; bad face planes and rule sets are refused naming the field.
/// (The plain loop implements the pass independently and the golden pins hold its behaviour:
/// test_plain_step.cpp, test_golden.cpp.)

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "quick_u_tube.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::test_def;
using granular::test::with_sparse;
using UTube = granular::test::QuickUTube;

namespace {

constexpr const char* kShallow = "inertial-24-shallow";

/// A closed tank `length` long and 8 wide on a solid floor, a block of liquid `height` high over its
/// first `block` columns (the accuracy suite's levelling tank, levelling_test.cpp).
Grid tank(int length, int height, int block, int top_room = 4) {
  const Int3 s{length, 8, 1 + height + top_room};
  Grid g(s);
  g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
  g.fill(Box{{0, 0, 1}, {block, s.y, 1 + height}}, Material::Liquid);
  return g;
}

/// The surface per slice x: liquid cells over the tank's width, in cells.
std::vector<double> surface(const World& w) {
  const Int3 s = w.size();
  const std::vector<std::uint8_t> cells = w.read_region(Box{{0, 0, 1}, s});
  std::vector<double> eta(std::size_t(s.x), 0.0);
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (cells[i] == to_cell(Material::Liquid)) eta[i % std::size_t(s.x)] += 1.0 / s.y;
  return eta;
}

/// The surface's largest distance from `level`.
double deviation(const std::vector<double>& eta, double level) {
  double d = 0;
  for (const double e : eta) d = std::max(d, std::abs(e - level));
  return d;
}

/// Steps `w` until its hash holds for `hold` ticks or `limit` ticks pass; returns the tick it
/// came to rest at (the last change), or -1.
long rest_tick(World& w, int limit, int hold = 64) {
  std::uint64_t last = w.hash();
  long since = long(w.tick());
  while (long(w.tick()) < limit) {
    w.step(1);
    const std::uint64_t h = w.hash();
    if (h != last) {
      last = h;
      since = long(w.tick());
    }
    if (long(w.tick()) - since >= hold) return since;
  }
  return -1;
}

}  // namespace

TEST_CASE("shallow water: a U-tube's legs level through the covered channel within one oscillation period, and come to rest") {
  // The oscillation period 2 pi sqrt(L / 2g) of a liquid column L = 56 cells long at g = 2 cells a
  // tick^2 is 23.5 ticks: real water has crossed the level after a quarter of it.
  const Grid g = UTube::build();
  World shallow(test_def(g.size(), kShallow, 2, 1), g);
  World flow(test_def(g.size(), "inertial-24-flow", 2, 1), g);
  shallow.step(24);
  flow.step(24);
  const double d_shallow = std::abs(UTube::level(shallow, 0) - UTube::level(shallow, UTube::kRight));
  const double d_flow = std::abs(UTube::level(flow, 0) - UTube::level(flow, UTube::kRight));
  CHECK_MESSAGE(d_shallow <= 1.0, "the legs stand " << d_shallow << " cells apart after 24 ticks");
  CHECK_MESSAGE(d_flow > 10.0, "the default rules levelled it too (" << d_flow << "): the test no longer tells them apart");
  const long rest = rest_tick(shallow, 600);
  CHECK_MESSAGE(rest >= 0, "still moving after 600 ticks");
  CHECK(std::abs(UTube::level(shallow, 0) - UTube::level(shallow, UTube::kRight)) <= 1.0);
  // Air the flow left under the wall stays there, as in a level pipe: at most a layer of it.
  CHECK(UTube::channel(shallow) >= long(UTube::kWall) * UTube::kLeg * (UTube::kChannelTop - 2));
  CHECK(shallow.count() == g.count());
  shallow.step(16);
  CHECK(shallow.activity().active_bricks == 0);
}

TEST_CASE("shallow water: the u_tube and reservoir scenes level through their pipes and come to rest at N = 96") {
  // Pipes 15 cells high and 19 long (u_tube) and 14 high and 29 long (reservoir): a pipe's flow
  // must die out as a pool's does, and the tower of the reservoir fill to within a cell or two of
  // the reservoir's surface (real water: both at 0.75 N).
  for (const char* name : {"u_tube", "reservoir"}) {
    CAPTURE(name);
    const SceneInstance scene = instantiate(load_scene(find_scene(name)), 96);
    World w(test_def(scene.grid.size(), kShallow, 2, 1), scene.grid);
    const long rest = rest_tick(w, 900);
    CHECK_MESSAGE(rest >= 0, "still moving after 900 ticks");
    CHECK(w.count() == scene.grid.count());
    w.step(16);
    CHECK(w.activity().active_bricks == 0);
    if (std::string(name) == "reservoir") {
      // The top of the water at the middle of the tower (x = 0.85 N) and of the reservoir (0.25 N).
      auto top = [&](int x) {
        for (int z = w.size().z - 1; z >= 0; --z)
          if (w.read_region(Box{{x, 8, z}, {x + 1, 9, z + 1}})[0] == to_cell(Material::Liquid)) return z;
        return -1;
      };
      CHECK(std::abs(top(81) - top(24)) <= 2);
      CHECK(top(81) >= 68);  // the tower has filled from 24 to near 72
    }
  }
}

TEST_CASE("shallow water: a burst dam runs on over the dry top of a pipe full of water") {
  // A floor 6 cells thick; a tunnel under it from x = 24 to 40, full of water and sealed; a block
  // of water 12 high over the first 12 columns. Without the tunnel the front passes x = 40 within
  // 100 ticks; with it, the tunnel must not hold the front at its edge.
  auto run = [](bool tunnel) {
    const Int3 s{64, 8, 24};
    Grid g(s);
    g.fill(Box{{0, 0, 0}, {s.x, s.y, 6}}, Material::Solid);
    if (tunnel) g.fill(Box{{24, 0, 1}, {40, s.y, 4}}, Material::Liquid);
    g.fill(Box{{0, 0, 6}, {12, s.y, 18}}, Material::Liquid);
    World w(test_def(s, kShallow, 2, 1), g);
    w.step(100);
    const std::vector<std::uint8_t> cells = w.read_region(Box{{40, 0, 6}, s});
    CHECK(w.count() == g.count());
    return std::count(cells.begin(), cells.end(), to_cell(Material::Liquid));
  };
  const auto open_floor = run(false), over_tunnel = run(true);
  CHECK(open_floor > 0);
  CHECK_MESSAGE(over_tunnel > 0, "no water passed x = 40 over the tunnel (" << open_floor << " cells without it)");
}

TEST_CASE("shallow water: a sealed cavity full of water, with no free surface, moves nothing") {
  const Int3 s{24, 8, 12};
  Grid g(s);
  g.fill(Box{{0, 0, 0}, s}, Material::Solid);
  g.fill(Box{{2, 1, 2}, {22, 7, 6}}, Material::Liquid);   // the cavity, full
  g.fill(Box{{2, 1, 7}, {10, 7, 10}}, Material::Liquid);  // a second one over it, full
  World w(test_def(s, kShallow, 2, 1), g);
  w.step(20);
  const Grid after = w.read_grid();
  CHECK(std::equal(after.cells().begin(), after.cells().end(), g.cells().begin()));
  CHECK(w.capture().faces.empty());
}

TEST_CASE("shallow water: a block of water levels in a closed tank within 5 shallow-water times, where the default rules leave it standing") {
  // L = 64, h = 4: L / sqrt(g h) = 22.6 ticks at g = 2 cells a tick^2, so 5 of them are 113 ticks.
  const Grid g = tank(64, 16, 16);
  World shallow(test_def(g.size(), kShallow, 2, 1), g);
  World flow(test_def(g.size(), "inertial-24-flow", 2, 1), g);
  shallow.step(113);
  flow.step(113);
  const double d_shallow = deviation(surface(shallow), 4.0), d_flow = deviation(surface(flow), 4.0);
  CHECK_MESSAGE(d_shallow <= 1.0, "the surface stands " << d_shallow << " cells from the level at rest");
  CHECK_MESSAGE(d_flow > 2.0, "the default rules levelled it too (" << d_flow << "): the test no longer tells them apart");
  CHECK(shallow.count() == g.count());
}

TEST_CASE("shallow water: sparse and dense stepping, on 1 and 2 threads, give the same cells and face plane") {
  for (const Grid& g : {tank(48, 12, 12), UTube::build()}) {
    std::vector<std::uint64_t> hashes;
    std::vector<std::int32_t> faces;
    for (const bool sparse : {true, false})
      for (const int threads : {1, 2}) {
        World w(with_sparse(test_def(g.size(), kShallow, threads, 7), sparse), g);
        w.step(16);
        hashes.push_back(w.hash());
        const WorldSnapshot s = w.capture();
        if (faces.empty()) faces = s.faces;
        CHECK(s.faces == faces);
        CHECK(w.count() == g.count());
      }
    CHECK_FALSE(faces.empty());  // mid-flow, some face moves
    for (const std::uint64_t h : hashes) CHECK(h == hashes.front());
  }
}

TEST_CASE("shallow water: a burst dam comes to rest as a whole, and its bricks then sleep") {
  const Grid g = tank(64, 12, 12);
  World w(test_def(g.size(), kShallow, 2, 3), g);
  const long rest = rest_tick(w, 1500);
  REQUIRE_MESSAGE(rest >= 0, "still moving after 1500 ticks");
  CHECK(w.capture().faces.empty() == false);  // the face plane holds the fractions of its level surface
  w.step(16);  // two sparse cycles with nothing moving
  CHECK(w.activity().active_bricks == 0);
  CHECK(w.count() == g.count());
}

TEST_CASE("shallow water: a deep pool with a partly filled top layer comes to rest, and its bricks sleep") {
  // 80 cells deep: a slow wave there carries a cell a tick across a face at a tenth of a cell a
  // tick, so the pool rests only if its last waves die out.
  const Int3 s{32, 32, 86};
  Grid g(s);
  g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
  g.fill(Box{{0, 0, 1}, {s.x, s.y, 81}}, Material::Liquid);
  for (int y = 0; y < s.y; ++y)
    for (int x = 0; x < s.x; ++x)
      if ((7 * x + 13 * y) % 11 == 0) g.cells()[g.index({x, y, 81})] = to_cell(Material::Liquid);
  World w(test_def(s, kShallow, 2, 3), g);
  const long rest = rest_tick(w, 600);
  CHECK_MESSAGE(rest >= 0, "still moving after 600 ticks");
  w.step(16);
  CHECK(w.activity().active_bricks == 0);
  CHECK(w.count() == g.count());
}

TEST_CASE("shallow water: a level pool with a partly filled top layer moves no cell and comes to rest") {
  Grid g = tank(40, 6, 40);
  // Every other cell of a seventh layer: a top layer half full, its surface level to half a cell.
  for (int y = 0; y < g.size().y; ++y)
    for (int x = 0; x < g.size().x; x += 2) g.cells()[g.index({x, y, 7})] = to_cell(Material::Liquid);
  World w(test_def(g.size(), kShallow, 2, 3), g);
  const long rest = rest_tick(w, 400);
  CHECK_MESSAGE(rest >= 0, "still moving after 400 ticks");
  // The faces hold the half cells (the surface they see is level); the cells never moved.
  const Grid after = w.read_grid();
  CHECK(std::equal(after.cells().begin(), after.cells().end(), g.cells().begin()));
  w.step(16);
  CHECK(w.activity().active_bricks == 0);
}

TEST_CASE("shallow water: a snapshot holds the face plane, and a world made from it continues bit-identically") {
  const Grid g = tank(48, 12, 12);
  World w(test_def(g.size(), kShallow, 2, 9), g);
  w.step(12);
  const WorldSnapshot s = w.capture();
  REQUIRE_FALSE(s.faces.empty());
  CHECK(s.faces.size() == 4 * std::size_t(g.size().x) * std::size_t(g.size().y));
  CHECK(s.hash() == w.hash());
  // Through the file: format version 5.
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "granular_shallow_snapshot.gsnap";
  save_snapshot(s, path);
  const WorldSnapshot loaded = load_snapshot(path);
  std::filesystem::remove(path);
  CHECK(loaded.faces == s.faces);
  const std::vector<std::uint8_t> bytes = encode_snapshot(s);
  CHECK(bytes[4] == kFacesSnapshotVersion);
  World resumed(test_def(g.size(), kShallow, 1, 9), loaded);
  CHECK(resumed.hash() == w.hash());
  w.step(30);
  resumed.step(30);
  CHECK(resumed.hash() == w.hash());
  // Restore into the first world: back to tick 12, then the same 30 ticks.
  w.restore(s);
  w.step(30);
  CHECK(w.hash() == resumed.hash());
}

TEST_CASE("shallow water: a face plane that cannot be the world's is refused, naming the field and the value") {
  const Grid g = tank(16, 4, 4);
  World w(test_def(g.size(), kShallow, 1, 1), g);
  w.step(4);
  WorldSnapshot s = w.capture();
  const std::size_t columns = std::size_t(g.size().x) * std::size_t(g.size().y);
  auto refused = [&](const WorldSnapshot& bad, const char* what) {
    CAPTURE(what);
    CHECK_THROWS_WITH_AS(w.restore(bad), doctest::Contains(what), InvalidArgument);
  };
  WorldSnapshot short_plane = s;
  short_plane.faces.assign(3, 1);
  refused(short_plane, "WorldSnapshot::faces holds 3 values");
  WorldSnapshot wall = s;
  wall.faces.assign(4 * columns, 0);
  wall.faces[std::size_t(g.size().x) - 1] = 5;  // the x face of the last column: the grid's edge
  refused(wall, "on the grid's edge, a wall");
  WorldSnapshot fraction = s;
  fraction.faces.assign(4 * columns, 0);
  fraction.faces[2 * columns] = 40000;  // an x fraction of more than a cell
  refused(fraction, "the x fraction of column (0, 0), is 40000");
  // A world without the lever keeps no face plane.
  World flow(test_def(g.size(), "inertial-24-flow", 1, 1), g);
  WorldSnapshot foreign = flow.capture();
  foreign.faces.assign(4 * columns, 0);
  foreign.faces[0] = 7;
  CHECK_THROWS_WITH_AS(flow.restore(foreign), doctest::Contains("RuleSet::motion.shallow = false"), InvalidArgument);
  // A world without liquid keeps none either (all zero is accepted: nothing moves).
  foreign.faces.assign(4 * columns, 0);
  CHECK_NOTHROW(flow.restore(foreign));
}

TEST_CASE("shallow water: the rule set checks refuse the lever without the motion model or with pressure") {
  RuleSet rules = preset(kShallow);
  CHECK_NOTHROW(validate_rule_set(rules));
  rules.motion.substeps = 1;
  CHECK_THROWS_WITH_AS(validate_rule_set(rules), doctest::Contains("RuleSet::motion.shallow = true with motion.substeps = 1"),
                       RuleError);
  rules = preset(kShallow);
  rules.motion.pressure = true;
  CHECK_THROWS_WITH_AS(validate_rule_set(rules), doctest::Contains("motion.shallow = true with motion.pressure = true"),
                       RuleError);
  // The lever is part of the rule set's fingerprint.
  RuleSet without = preset(kShallow);
  without.motion.shallow = false;
  CHECK(rule_fingerprint(without) != rule_fingerprint(preset(kShallow)));
}
