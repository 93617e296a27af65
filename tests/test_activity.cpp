// Sparse stepping (activity tracking): the same grid as dense stepping, bricks that really sleep,
// and exact change reports. The CUDA counterparts are in gpu/test_cuda_backend.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>

#include "granular/extend/lut.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "step/motion_block.hpp"
#include "step/motion_table.hpp"
#include "test_support.hpp"

using namespace granular;
using namespace granular::test;

namespace {

/// A random tool call on both worlds (dig, pour, paint box or sphere), the same on each.
void random_tool(std::mt19937_64& rng, World& a, World& b) {
  const Int3 n = a.size();
  std::uniform_real_distribution<double> ux(0, n.x), uy(0, n.y), uz(0, n.z), ur(1.0, 6.0);
  const Vec3 c{ux(rng), uy(rng), uz(rng)};
  const double r = ur(rng);
  switch (rng() % 4) {
    case 0:
      CHECK(a.dig({c, r}).cells_changed == b.dig({c, r}).cells_changed);
      break;
    case 1:
      CHECK(a.pour(c, r, Material::Granular, 40).cells_changed == b.pour(c, r, Material::Granular, 40).cells_changed);
      break;
    case 2: {
      const Int3 lo{int(c.x), int(c.y), int(c.z)};
      const Box box{lo, {lo.x + 1 + int(rng() % 5), lo.y + 1 + int(rng() % 5), lo.z + 1 + int(rng() % 3)}};
      const Material m = rng() % 3 == 0 ? Material::Solid : Material::Granular;
      CHECK(a.paint(box, m).cells_changed == b.paint(box, m).cells_changed);
      break;
    }
    default:
      CHECK(a.paint(Sphere{c, r}, Material::Void).cells_changed == b.paint(Sphere{c, r}, Material::Void).cells_changed);
      break;
  }
}

/// The bricks whose cells differ between two grids of one size.
std::set<std::uint32_t> differing_bricks(const Grid& before, const Grid& after) {
  std::set<std::uint32_t> out;
  const Int3 n = brick_counts(before.size());
  for (int z = 0; z < before.size().z; ++z)
    for (int y = 0; y < before.size().y; ++y)
      for (int x = 0; x < before.size().x; ++x)
        if (before.at({x, y, z}) != after.at({x, y, z}))
          out.insert(std::uint32_t(((z / kBrickSize) * n.y + y / kBrickSize) * n.x + x / kBrickSize));
  return out;
}

}  // namespace

TEST_CASE("activity: sparse stepping gives the dense hash on random scenes, odd sizes, both rule sets, mixed step calls and tools") {
  std::mt19937_64 rng(2024);
  for (int round = 0; round < 6; ++round) {
    const Int3 size = random_size(rng, 17, 61);
    const char* rules = round % 3 == 0 ? "paper" : round % 3 == 1 ? "isotropic" : "inertial";
    const std::uint64_t seed = rng();
    // Sparse grains over a floor of settled sand: most bricks fall asleep, tools wake some.
    Grid initial = random_grid(size, seed, 6, 12);
    for (int z = 0; z < size.z / 3; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
          if (initial.at({x, y, z}) == Material::Void) initial.set({x, y, z}, Material::Granular);
    CAPTURE(round);
    CAPTURE(rules);
    CAPTURE(size);
    World dense(with_sparse(test_def(size, rules, 2, seed), false), initial);
    World sparse(with_sparse(test_def(size, rules, 2, seed), true), initial);
    std::uint64_t slept = ~std::uint64_t(0);
    for (int call = 0; call < 60; ++call) {
      const int ticks = int(rng() % 23);  // any parity, across cycle boundaries, zero included
      dense.step(ticks);
      sparse.step(ticks);
      REQUIRE(sparse.hash() == dense.hash());
      if (ticks > 0) slept = std::min(slept, sparse.activity().active_bricks);
      if (rng() % 3 == 0) random_tool(rng, dense, sparse);
      REQUIRE(sparse.hash() == dense.hash());
    }
    CHECK(sparse.read_grid().cells().size() == dense.read_grid().cells().size());
    CHECK(slept < sparse.activity().total_bricks);  // sparse stepping did skip bricks
  }
}

TEST_CASE("activity: long runs stay equal to dense stepping, from a falling block to rest") {
  for (const char* rules : {"paper", "isotropic", "inertial"}) {
    CAPTURE(rules);
    const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), 45);
    World dense(with_sparse(test_def(scene.grid.size(), rules, 2, 77), false), scene.grid);
    World sparse(with_sparse(test_def(scene.grid.size(), rules, 2, 77), true), scene.grid);
    for (int call = 0; call < 12; ++call) {
      dense.step(333);
      sparse.step(333);
      REQUIRE(sparse.hash() == dense.hash());
    }
  }
}

TEST_CASE("activity: fast grains poured mid-cycle fall through sleeping bricks exactly as with dense stepping") {
  // With the motion model a grain falls up to 15 cells per tick, so within one 8-tick cycle it would
  // leave the bricks woken around a tool's region: the sparse cycle is 8 sub-steps instead.
  for (const char* rules : {"inertial", "inertial-24"}) {
    CAPTURE(rules);
    const Int3 size{21, 19, 120};
    World dense(with_sparse(test_def(size, rules, 2, 9), false));
    World sparse(with_sparse(test_def(size, rules, 2, 9), true));
    for (World* w : {&dense, &sparse}) {
      w->paint(Box{{0, 0, 0}, {size.x, size.y, 1}}, Material::Solid);
      w->paint(Box{{0, 0, 1}, {size.x, size.y, 6}}, Material::Granular);
      w->step(16);
    }
    REQUIRE(sparse.hash() == dense.hash());
    REQUIRE(sparse.activity().active_bricks == 0);
    for (int round = 0; round < 3; ++round) {
      dense.step(3 + round);
      sparse.step(3 + round);
      CAPTURE(round);
      for (World* w : {&dense, &sparse}) w->pour({10.5, 9.5, 112.0 - 20 * round}, 3.0, Material::Granular, 40);
      for (int t = 0; t < 24; ++t) {
        dense.step(1);
        sparse.step(1);
        CAPTURE(t);
        REQUIRE(sparse.hash() == dense.hash());
      }
    }
    CHECK(sparse.count() == dense.count());
  }
}

TEST_CASE("activity: load() and single ticks across cycle boundaries match dense stepping") {
  const Int3 size{35, 34, 33};
  World dense(with_sparse(test_def(size, "isotropic", 1, 5), false), random_grid(size, 3, 5, 20));
  World sparse(with_sparse(test_def(size, "isotropic", 2, 5), true), random_grid(size, 3, 5, 20));
  for (int t = 0; t < 300; ++t) {
    dense.step(1);
    sparse.step(1);
    REQUIRE(sparse.hash() == dense.hash());
    if (t == 150) {
      const Grid other = random_grid(size, 11, 5, 30);
      dense.load(other);
      sparse.load(other);
    }
  }
}

TEST_CASE("activity: a settled scene goes to zero active bricks and costs nothing to step") {
  const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), 48);
  World world(test_def(scene.grid.size()), scene.grid);
  world.step(8);
  CHECK(world.activity().active_bricks == world.activity().total_bricks);
  CHECK(world.activity().ticks == 8);
  CHECK(world.activity().brick_ticks == 8 * world.activity().total_bricks);
  CHECK(world.activity().cell_ticks == 8 * 48ull * 48 * 48);
  std::uint64_t ticks = 0;
  while (world.activity().active_bricks > 0 && ticks < 20000) {
    world.step(64);
    ticks += 64;
  }
  REQUIRE(world.activity().active_bricks == 0);
  CHECK(world.activity().active_cells == 0);
  const std::uint64_t hash = world.hash();
  const std::uint64_t version = world.change_version();
  world.step(100);
  CHECK(world.activity().brick_ticks == 0);
  CHECK(world.hash() == hash);
  CHECK(world.bricks_changed_since(version).empty());
  CHECK(world.change_version() == version);
}

TEST_CASE("activity: a pour in one corner of a settled world wakes only the bricks near it") {
  const Int3 size{96, 96, 64};
  Grid floor(size);
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) floor.set({x, y, z}, Material::Granular);
  World world(test_def(size), floor);
  World dense(with_sparse(test_def(size), false), floor);
  world.step(24);  // cycle 0 wakes all (construction), cycle 1 finds everything inert, cycle 2 sleeps
  dense.step(24);
  REQUIRE(world.activity().active_bricks == 0);
  std::uint64_t most = 0;
  for (int t = 0; t < 200; ++t) {
    world.pour({8, 8, 40}, 3, Material::Granular, 6);
    dense.pour({8, 8, 40}, 3, Material::Granular, 6);
    world.step(1);
    dense.step(1);
    most = std::max(most, world.activity().active_bricks);
  }
  CHECK(world.hash() == dense.hash());
  // The stream and its heap lie in bricks x, y < 2; with their neighbours at most 3 x 3 x 4.
  CHECK(most > 0);
  CHECK(most <= 36);
  CHECK(world.activity().total_bricks == 6 * 6 * 4);
  const std::uint64_t version = world.change_version();
  world.step(8);
  for (const std::uint32_t b : world.bricks_changed_since(version)) {
    const Box box = brick_box(size, b);
    CHECK(box.min.x < 32);
    CHECK(box.min.y < 32);
  }
}

TEST_CASE("activity: bricks_changed_since lists exactly the bricks whose cells changed") {
  const Int3 size{37, 50, 41};
  for (const char* rules : {"paper", "isotropic", "inertial"}) {
    CAPTURE(rules);
    World world(test_def(size, rules, 2, 3), random_grid(size, 8, 5, 15));
    std::mt19937_64 rng(5);
    for (int t = 0; t < 120; ++t) {
      const Grid before = world.read_grid();
      const std::uint64_t version = world.change_version();
      if (t % 10 == 5) {
        World twin(test_def(size, rules, 2, 3), before);
        random_tool(rng, world, twin);
      } else {
        world.step(1);  // one tick writes each cell at most once
      }
      const auto listed = world.bricks_changed_since(version);
      const std::set<std::uint32_t> got(listed.begin(), listed.end());
      const std::set<std::uint32_t> differing = differing_bricks(before, world.read_grid());
      if (world.rules().motion.enabled()) {
        // Cell bytes also hold the grains' motion state, which a snapshot leaves out: the list
        // holds every brick whose materials changed, and those where only a grain's motion did.
        REQUIRE(std::includes(got.begin(), got.end(), differing.begin(), differing.end()));
      } else {
        REQUIRE(got == differing);
      }
    }
  }
}

TEST_CASE("activity: dense stepping reports every brick active and changed") {
  const Int3 size{33, 20, 17};
  World world(with_sparse(test_def(size), false), random_grid(size, 1));
  const std::uint64_t version = world.change_version();
  world.step(5);
  CHECK(world.activity().active_bricks == world.activity().total_bricks);
  CHECK(world.activity().cell_ticks == 5ull * 33 * 20 * 17);
  CHECK(world.bricks_changed_since(version).size() == world.activity().total_bricks);
}

TEST_CASE("activity: grids holding all 8 states (reserved ones are obstacles) match dense stepping") {
  for (const char* rules : {"paper", "isotropic", "inertial"}) {
    CAPTURE(rules);
    const Int3 size{29, 40, 36};
    const Grid initial = random_grid_all_states(size, 12);
    World dense(with_sparse(test_def(size, rules, 2, 4), false), initial);
    World sparse(with_sparse(test_def(size, rules, 2, 4), true), initial);
    for (const int ticks : {5, 8, 13, 64, 200}) {
      dense.step(ticks);
      sparse.step(ticks);
      REQUIRE(sparse.hash() == dense.hash());
    }
  }
}

TEST_CASE("activity: a block whose reach is below s + 2 stays as it is in sub-step s (what lets a brick be idle)") {
  WorldDef def;
  def.rules = "inertial-24";
  const World world(def);
  const RuleSet& rules = world.rules();
  const StepMaterials mats = step_materials(rules.materials);
  const std::vector<motion::MotionEntry> entries = derive_motion_table(world.lut().entries());
  const int max_level = rules.motion.max_level();
  std::mt19937_64 rng(7);
  int idle_blocks = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::uint64_t bytes = 0;
    std::uint32_t plain_reach = 0;
    for (int i = 0; i < 8; ++i) {
      const std::uint32_t m = std::uint32_t(rng() % kMaterialCount);
      std::uint32_t byte = m;
      if (mats.is_faller(m)) {
        // Mostly slow fallers, so that many blocks have a low reach.
        const std::uint32_t level = rng() % 3 == 0 ? std::uint32_t(rng() % (max_level + 1)) : std::uint32_t(rng() % 3);
        const std::uint32_t start = std::uint32_t(rng() & 1u);
        byte |= (level << kMotionShift) | (start << 7);
        plain_reach = std::max(plain_reach, 2 * level + start);
      }
      bytes |= std::uint64_t(byte) << (8 * i);
    }
    REQUIRE(motion::reach_of(bytes) == plain_reach);
    const std::uint64_t tick = rng() % 1000;
    for (int s = 2; s < rules.motion.substeps; ++s) {
      if (plain_reach >= std::uint32_t(s) + 2) continue;
      ++idle_blocks;
      const motion::SubStep sub = motion::sub_step(rules.motion, mats, 3, tick, s, rules.random_symmetry);
      const std::uint64_t after =
          motion::step_block(bytes, sub, 2 * int(rng() % 64), 2 * int(rng() % 64), 2 * int(rng() % 64),
                             [&](std::uint32_t k) { return entries[k]; });
      REQUIRE(after == bytes);
    }
  }
  CHECK(idle_blocks > 100000);
}
