/// @file test_columns.cpp
/// The motion model's columns lever and its trains (MotionParams::columns and ::trains, preset
/// inertial-24-columns): a released block falls in free-fall time and stays a block, past the packing
/// one-cell moves allow, its grains against a wall keeping up with the rest and none slowed to the
/// flow level by slipping past another; a body in free fall is carried, falling g t^2 / 2 a tick with
/// its inside asleep, and tools, snapshots and landing lose nothing of it; wakes never outlive their
/// sub-step, a settled world under the levers sleeps, and worlds, snapshots and rule sets hold or
/// refuse wake bytes as the lever says. (The plain loop and the golden pins cover the lever cell for
/// cell: test_plain_step.cpp, test_golden.cpp.)

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "granular/motion.hpp"
#include "granular/rule_presets.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::check_has;
using granular::test::error_of;
using granular::test::test_def;
using granular::test::with_sparse;

namespace {

/// How a released cube of sand fell: ticks until its mean height dropped two side lengths, and its
/// packing then (grains in its footprint between its 5th and 95th percentile layers over those cells).
struct Fall {
  int ticks = 0;
  double packing = 0;
};

Fall drop_block(const std::shared_ptr<const RuleSet>& rules, int side) {
  const int margin = 4, clearance = 12 * side;
  const Int3 size{side + 2 * margin, side + 2 * margin, clearance + side + 4};
  WorldDef def = test_def(size, rules->name.c_str(), 2, 5);
  def.rule_set = rules;
  World world(def);
  world.paint(Box{{margin, margin, clearance}, {margin + side, margin + side, clearance + side}}, Material::Granular);
  auto layers = [&] {
    std::vector<double> grains(std::size_t(size.z), 0);
    const std::vector<std::uint8_t> cells = world.read_region(Box{{0, 0, 0}, size});
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (cells[i] == to_cell(Material::Granular)) grains[i / std::size_t(size.x * size.y)] += 1;
    return grains;
  };
  auto centre = [](const std::vector<double>& g) {
    double sum = 0, n = 0;
    for (std::size_t z = 0; z < g.size(); ++z) sum += g[z] * (double(z) + 0.5), n += g[z];
    return sum / n;
  };
  const double start = centre(layers());
  Fall f;
  std::vector<double> g = layers();
  while (start - centre(g) < 2.0 * side && f.ticks < 400) {
    world.step(1);
    ++f.ticks;
    g = layers();
  }
  const double total = double(side) * side * side;
  int lo = 0, hi = 0;
  double below = 0;
  for (int z = 0; z < size.z; ++z) {
    below += g[std::size_t(z)];
    if (below < 0.05 * total) lo = z + 1;
    if (below < 0.95 * total) hi = z + 1;
  }
  double in = 0;
  for (int z = lo; z <= hi; ++z) in += g[std::size_t(z)];
  f.packing = in / (double(side) * side * (hi - lo + 1));
  return f;
}

Fall drop_block(const char* rules, int side) { return drop_block(make_rule_set(rules), side); }

/// True when some cell byte of `world` is a wake.
bool holds_wake(const World& world) {
  for (const std::uint8_t c : world.capture().cells)
    if (is_wake(c)) return true;
  return false;
}

}  // namespace

TEST_CASE("columns: a released block falls two of its heights in free-fall time and stays a block") {
  const int side = 16;
  const double g = 2.0;  // cells per tick^2 under the 24-sub-step presets (motion.hpp)
  const double free_fall = std::sqrt(2 * 2.0 * side / g);
  const Fall with = drop_block("inertial-24-columns", side);
  const Fall without = drop_block("inertial-24", side);
  CAPTURE(with.ticks);
  CAPTURE(with.packing);
  CAPTURE(without.ticks);
  CAPTURE(without.packing);
  // Each tick of the lever's fall is a free-fall tick: at most one tick more than g t^2 / 2 needs.
  CHECK(with.ticks <= int(std::ceil(free_fall)) + 1);
  // Without the lever the block peels off layer by layer: several times slower, and spread thin.
  CHECK(without.ticks >= 3 * with.ticks);
  CHECK(with.packing >= 0.4);
  CHECK(with.packing >= 3 * without.packing);
}

TEST_CASE("columns: a grain slipping past a fast-falling grain keeps its speed, so a falling block has no slow grains") {
  // The preset's grain has a flow level of 1: a grain that rolls or topples over a surface keeps at
  // most level 1. Inside a falling body a grain blocked by a slower grain below it rolls too; under
  // the lever it keeps its level when the grain under it falls at level 2 or faster. Without that,
  // about 2,000 of this block's 32,768 grains sit at level 1 from the fourth tick on and the block
  // spreads (packing 0.43 against 0.56 when it has fallen two of its heights).
  const std::shared_ptr<const RuleSet> rules = make_rule_set("inertial-24-columns");
  REQUIRE(rules->materials[to_cell(Material::Granular)].grain.flow_level == 1);
  const int side = 32, margin = 8, clearance = 400;
  const Int3 size{side + 2 * margin, side + 2 * margin, clearance + side + 4};
  World world(test_def(size, "inertial-24-columns", 2, 5));
  world.paint(Box{{margin, margin, clearance}, {margin + side, margin + side, clearance + side}}, Material::Granular);
  world.step(4);  // the block's grains have left rest
  for (int tick = 5; tick <= 10; ++tick) {
    world.step(1);
    int slow = 0, grains = 0;
    for (const std::uint8_t c : world.capture().cells) {
      if (cell_material(c) != to_cell(Material::Granular)) continue;
      ++grains;
      slow += cell_motion(c) <= 1 ? 1 : 0;
    }
    CAPTURE(tick);
    CHECK(grains == side * side * side);  // still in the air
    CHECK(slow == 0);
  }
}

TEST_CASE("columns: a mid-sized block keeps its packing: an airborne train takes in grains of every moving level") {
  // The sub-steps' windows give a falling column grains of neighbouring levels; trains of one level
  // each left gaps between them that never closed, and a 32-cell block kept 0.56 of its packing after
  // falling two of its heights. An airborne train takes its grains in whatever their level.
  const int side = 32;
  const double free_fall = std::sqrt(2 * 2.0 * side / 2.0);
  const Fall f = drop_block("inertial-24-columns", side);
  CAPTURE(f.ticks);
  CAPTURE(f.packing);
  CHECK(f.packing >= 0.9);
  CHECK(f.ticks <= int(std::ceil(free_fall)) + 1);
}

TEST_CASE("columns: grains against a wall fall as fast as the rest of their block") {
  // A block that fills a walled shaft wall to wall: gravity accelerates every grain in free fall,
  // so the grains beside the walls keep up with the middle of the block.
  const int side = 16, clearance = 12 * side;
  const Int3 size{side + 2, side + 2, clearance + side + 4};
  World world(test_def(size, "inertial-24-columns", 2, 5));
  for (const Box& wall : {Box{{0, 0, 0}, {1, size.y, size.z}}, Box{{size.x - 1, 0, 0}, {size.x, size.y, size.z}},
                          Box{{0, 0, 0}, {size.x, 1, size.z}}, Box{{0, size.y - 1, 0}, {size.x, size.y, size.z}}})
    world.paint(wall, Material::Solid);
  world.paint(Box{{1, 1, clearance}, {side + 1, side + 1, clearance + side}}, Material::Granular);
  // Mean height of the grains in the columns beside a wall and in the others.
  auto heights = [&] {
    const std::vector<std::uint8_t> cells = world.read_region(Box{{0, 0, 0}, size});
    double sum[2] = {}, n[2] = {};
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (cells[i] != to_cell(Material::Granular)) continue;
      const int x = int(i % std::size_t(size.x)), y = int(i / std::size_t(size.x) % std::size_t(size.y));
      const int z = int(i / std::size_t(size.x * size.y));
      const int beside = x == 1 || x == side || y == 1 || y == side ? 1 : 0;
      sum[beside] += z;
      n[beside] += 1;
    }
    return std::array<double, 2>{sum[0] / n[0], sum[1] / n[1]};
  };
  const double start = heights()[0];
  int ticks = 0;
  while (start - heights()[0] < 1.5 * side && ticks < 100) {
    world.step(1);
    ++ticks;
  }
  const std::array<double, 2> h = heights();
  CAPTURE(ticks);
  CAPTURE(h[0]);
  CAPTURE(h[1]);
  CHECK(start - h[0] >= 1.5 * side);
  CHECK(std::abs(h[1] - h[0]) <= 2.0);
}

TEST_CASE("trains: a released block keeps its packing past the bound that one-cell moves set") {
  const int side = 16;
  const std::shared_ptr<const RuleSet> trains = make_rule_set("inertial-24-columns");
  REQUIRE(trains->motion.trains);
  auto wakes_only = std::make_shared<RuleSet>(*trains);
  wakes_only->motion.trains = false;
  const Fall with = drop_block(trains, side);
  const Fall without = drop_block(wakes_only, side);
  // The bound: a column falling v cells a sub-step holds at most 1 / (1 + v) of its cells, v the
  // speed after the fall of 2 side lengths (g = 2 cells per tick^2, 24 sub-steps a tick).
  const double v = std::sqrt(2 * 2.0 * 2.0 * side) / 24;
  const double bound = 1 / (1 + v);
  CAPTURE(with.ticks);
  CAPTURE(with.packing);
  CAPTURE(without.ticks);
  CAPTURE(without.packing);
  CAPTURE(bound);
  CHECK(without.packing < bound);
  CHECK(with.packing > bound);
  CHECK(with.packing >= 1.5 * without.packing);
  CHECK(with.ticks <= without.ticks);  // closing the gaps never slows the fall
}

TEST_CASE("trains: the lever needs columns and a World; its rule sets fingerprint apart") {
  RuleSet rules = preset("inertial-24-columns");
  const std::uint64_t on = rule_fingerprint(rules);
  rules.motion.trains = false;
  CHECK(rule_fingerprint(rules) != on);
  rules.motion.trains = true;
  rules.motion.columns = false;
  check_has(error_of<RuleError>([&] { validate_rule_set(rules); }), {"RuleSet::motion.trains = true", "columns = false"});
}

TEST_CASE("columns: the bowl falls, settles and sleeps; sparse equals dense and no wake outlives its sub-step") {
  const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), 40);
  World dense(with_sparse(test_def(scene.grid.size(), "inertial-24-columns", 2, 9), false), scene.grid);
  World sparse(with_sparse(test_def(scene.grid.size(), "inertial-24-columns", 2, 9), true), scene.grid);
  const MaterialCounts counts = dense.count();
  bool saw_wake = false;
  for (int call = 0; call < 40; ++call) {
    const int ticks = 1 + call % 7;  // odd and even calls, across cycles
    dense.step(ticks);
    sparse.step(ticks);
    REQUIRE(sparse.hash() == dense.hash());
    saw_wake = saw_wake || holds_wake(dense);
  }
  CHECK(saw_wake);  // the lever was at work
  sparse.step(3000);
  dense.step(3000);
  CHECK(sparse.hash() == dense.hash());
  CHECK(dense.count() == counts);
  CHECK_FALSE(holds_wake(dense));
  sparse.step(16);
  CHECK(sparse.activity().active_bricks == 0);  // a settled world under the lever costs nothing
}

TEST_CASE("columns: a snapshot taken while wakes are in the cells continues as the world that never stopped") {
  const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), 32);
  const WorldDef def = test_def(scene.grid.size(), "inertial-24-columns", 2, 3);
  World original(def, scene.grid);
  WorldSnapshot captured;
  for (int tick = 0; tick < 60; ++tick) {
    original.step(1);
    captured = original.capture();
    if (std::any_of(captured.cells.begin(), captured.cells.end(), [](std::uint8_t c) { return is_wake(c); }))
      break;
  }
  REQUIRE(std::any_of(captured.cells.begin(), captured.cells.end(), [](std::uint8_t c) { return is_wake(c); }));
  World continued(def, captured);
  CHECK(continued.hash() == original.hash());
  original.step(30);
  continued.step(30);
  CHECK(continued.hash() == original.hash());

  // A wake is a byte only the lever's rules hold.
  WorldDef other = def;
  other.rules = "inertial-24";
  captured.rules = "inertial-24";
  captured.rule_fingerprint = rule_fingerprint(preset("inertial-24"));
  check_has(error_of<InvalidArgument>([&] { World w(other, captured); }), {"holds the byte", "neither granular nor liquid"});
}

TEST_CASE("columns: the lever needs a motion model; its rule sets fingerprint apart") {
  RuleSet rules = preset("inertial-24");
  const std::uint64_t off = rule_fingerprint(rules);
  rules.motion.columns = true;
  CHECK(rule_fingerprint(rules) != off);
  RuleSet one_step = preset("isotropic");
  one_step.motion.columns = true;
  check_has(error_of<RuleError>([&] { validate_rule_set(one_step); }), {"RuleSet::motion.columns = true", "substeps = 1"});
}

namespace {

/// The grains of `world` that are carried (their level bits kCarriedLevel), and all its grains.
std::array<int, 2> carried_grains(const World& world) {
  std::array<int, 2> n{};
  for (const std::uint8_t c : world.capture().cells) {
    if (cell_material(c) != to_cell(Material::Granular)) continue;
    ++n[1];
    n[0] += cell_motion(c) == kCarriedLevel ? 1 : 0;
  }
  return n;
}

/// The lowest layer of `world` holding at least `grains` grains (its size.z when none does).
int lowest_layer(const World& world, Int3 size, int grains) {
  const std::vector<std::uint8_t> cells = world.read_region(Box{{0, 0, 0}, size});
  const std::size_t layer = std::size_t(size.x) * std::size_t(size.y);
  for (int z = 0; z < size.z; ++z)
    if (std::count(cells.begin() + std::ptrdiff_t(z * layer), cells.begin() + std::ptrdiff_t((z + 1) * layer),
                   to_cell(Material::Granular)) >= grains)
      return z;
  return size.z;
}

}  // namespace

TEST_CASE("carried trains: a block in free fall is moved whole by the trains pass, and its inside sleeps") {
  // A block filling a walled shaft wall to wall, released from rest, falls 1 and 3 cells in its first
  // two ticks through the block step; then, airborne, it is carried: each tick the pass moves it a
  // tick's travel at its next level (5, 7, 9, ... cells: g t^2 / 2 with g = 2), and the block step
  // reads its grains as a static material, so the bricks inside it sleep and only those at its front
  // (its sweep) and its back (the cells it left) wake.
  const int side = 32, height = 512, clearance = 200;
  const Int3 size{side + 2, side + 2, clearance + height + 4};
  World dense(with_sparse(test_def(size, "inertial-24-columns", 2, 5), false));
  World sparse(with_sparse(test_def(size, "inertial-24-columns", 2, 5), true));
  for (World* w : {&dense, &sparse}) {
    for (const Box& wall : {Box{{0, 0, 0}, {1, size.y, size.z}}, Box{{size.x - 1, 0, 0}, {size.x, size.y, size.z}},
                            Box{{0, 0, 0}, {size.x, 1, size.z}}, Box{{0, size.y - 1, 0}, {size.x, size.y, size.z}}})
      w->paint(wall, Material::Solid);
    w->paint(Box{{1, 1, clearance}, {side + 1, side + 1, clearance + height}}, Material::Granular);
  }
  const std::uint64_t layer_bricks = std::uint64_t((size.x + kBrickSize - 1) / kBrickSize) * ((size.y + kBrickSize - 1) / kBrickSize);
  const std::uint64_t body_bricks = layer_bricks * std::uint64_t(height / kBrickSize);
  for (int t = 1; t <= 12; ++t) {  // tick 12 reaches the rules' top speed, 23 cells a tick
    dense.step(1);
    sparse.step(1);
    REQUIRE(sparse.hash() == dense.hash());
    CAPTURE(t);
    CHECK(clearance - lowest_layer(dense, size, side * side / 2) == t * t);  // free fall, tick for tick
    if (t >= 3) {
      const std::array<int, 2> n = carried_grains(dense);
      CHECK(n[0] == n[1]);  // every grain rides in one carried train
    }
    if (t >= 4) {
      // Awake: the bricks within a tick's travel of the body's front and back, and their neighbours;
      // the wakes alone kept every brick of the body awake.
      CAPTURE(sparse.activity().active_bricks);
      CHECK(sparse.activity().active_bricks < body_bricks / 2);
    }
  }
  CHECK(dense.count() == sparse.count());
}

TEST_CASE("carried trains: a train cut by tools, a snapshot of one, and its landing lose nothing") {
  const int side = 24, margin = 6, clearance = 150;
  const Int3 size{side + 2 * margin, side + 2 * margin, clearance + side + 4};
  const WorldDef dense_def = with_sparse(test_def(size, "inertial-24-columns", 2, 7), false);
  World dense(dense_def);
  World sparse(with_sparse(test_def(size, "inertial-24-columns", 2, 7), true));
  const Box block{{margin, margin, clearance}, {margin + side, margin + side, clearance + side}};
  for (World* w : {&dense, &sparse}) {
    w->paint(block, Material::Granular);
    w->step(5);
  }
  REQUIRE(carried_grains(dense)[0] == side * side * side);
  // A snapshot of a carried train continues as the world that never stopped.
  World restored(dense_def, dense.capture());
  CHECK(restored.hash() == dense.hash());
  // Tools cut the train: a slab dug out of its middle, a column of its sweep painted solid, a pour
  // of sand into the void under it. Every backend and mode heals the train alike.
  const int bottom = lowest_layer(dense, size, side * side / 2);
  for (World* w : {&dense, &sparse, &restored}) {
    w->paint(Box{{margin, margin, bottom + 10}, {margin + side, margin + side / 2, bottom + 12}}, Material::Void);
    w->paint(Box{{margin + 3, margin + 3, bottom - 4}, {margin + 4, margin + 4, bottom}}, Material::Solid);
    w->paint(Box{{margin + side - 4, margin + side - 4, bottom - 30}, {margin + side, margin + side, bottom - 28}},
             Material::Granular);
  }
  const MaterialCounts counts = dense.count();
  for (int call = 0; call < 30; ++call) {
    const int ticks = 1 + call % 5;
    dense.step(ticks);
    sparse.step(ticks);
    restored.step(ticks);
    REQUIRE(sparse.hash() == dense.hash());
    REQUIRE(restored.hash() == dense.hash());
  }
  CHECK(dense.count() == counts);
  // Landed and settled: no grain is carried and no void swept any more, and the world sleeps.
  dense.step(600);
  sparse.step(600);
  CHECK(sparse.hash() == dense.hash());
  CHECK(carried_grains(dense)[0] == 0);
  for (const std::uint8_t c : dense.capture().cells)
    if (cell_material(c) == to_cell(Material::Void)) REQUIRE(c == 0);
  sparse.step(16);
  CHECK(sparse.activity().active_bricks == 0);
}

TEST_CASE("carried trains: a carried grain's mark is a motion level no rule set with trains gives a grain") {
  RuleSet rules = preset("inertial-24-columns");
  rules.motion.substeps = 32;  // its highest level would be kCarriedLevel itself
  check_has(error_of<RuleError>([&] { validate_rule_set(rules); }), {"RuleSet::motion.trains = true", "substeps = 32"});
  rules.motion.substeps = 24;
  validate_rule_set(rules);
}
