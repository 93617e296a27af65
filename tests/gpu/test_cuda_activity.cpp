/// @file test_cuda_activity.cpp
/// Sparse stepping on the CUDA backend: the same grid as dense stepping on the CPU for any scene,
/// size, seed, rule set, step lengths and tools between ticks; and the same bookkeeping as the
/// CPU's sparse stepping (active bricks and cells per tick, changed bricks), which follows the same
/// sleep/wake rules, so every figure must agree exactly.

#include <doctest/doctest.h>

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "../test_support.hpp"
#include "granular/errors.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"

using namespace granular;
using granular::test::random_grid;
using granular::test::random_size;

namespace {

/// A WorldDef for `backend` (the CPU with 2 threads), sparse or dense, with the build tree's table cache.
WorldDef activity_def(BackendKind backend, bool sparse, const char* rules, std::uint64_t seed) {
  WorldDef def;
  def.rules = rules;
  def.seed = seed;
  def.backend = backend;
  def.threads = 2;
  def.sparse = sparse;
  return def;
}

/// The reference (dense CPU), the CPU's sparse stepping and the GPU's, from one grid.
struct Trio {
  World dense;
  World cpu;
  World gpu;
  Trio(const Grid& initial, const char* rules, std::uint64_t seed)
      : dense(activity_def(BackendKind::Cpu, false, rules, seed), initial),
        cpu(activity_def(BackendKind::Cpu, true, rules, seed), initial),
        gpu(activity_def(BackendKind::Cuda, true, rules, seed), initial) {}
  /// Steps all three.
  void step(int ticks) {
    dense.step(ticks);
    cpu.step(ticks);
    gpu.step(ticks);
  }
  /// Applies `tool` to each of the three worlds, in order.
  template <class Tool>
  void each(Tool&& tool) {
    tool(dense);
    tool(cpu);
    tool(gpu);
  }
};

/// "" when both worlds hold the same cells, else the first differing cell and both values.
std::string first_difference(const World& a, const World& b) {
  const Grid x = a.snapshot(), y = b.snapshot();
  for (int k = 0; k < x.size().z; ++k)
    for (int j = 0; j < x.size().y; ++j)
      for (int i = 0; i < x.size().x; ++i)
        if (x.at({i, j, k}) != y.at({i, j, k}))
          return "first difference at (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                 "): dense cpu " + std::to_string(unsigned(to_cell(x.at({i, j, k})))) + ", sparse gpu " +
                 std::to_string(unsigned(to_cell(y.at({i, j, k})))) + " at tick " + std::to_string(a.tick());
  return {};
}

/// Sparse GPU == dense CPU (cells), and the GPU's activity figures == the sparse CPU's.
void require_same(const Trio& w) {
  const std::uint64_t reference = w.dense.hash(), gpu = w.gpu.hash();
  if (gpu != reference) FAIL_CHECK(first_difference(w.dense, w.gpu));
  REQUIRE(gpu == reference);
  REQUIRE(w.cpu.hash() == reference);
  const ActivityStats a = w.cpu.activity(), b = w.gpu.activity();
  CHECK(b.total_bricks == a.total_bricks);
  CHECK(b.ticks == a.ticks);
  CHECK(b.active_bricks == a.active_bricks);
  CHECK(b.active_cells == a.active_cells);
  CHECK(b.brick_ticks == a.brick_ticks);
  CHECK(b.cell_ticks == a.cell_ticks);
}

/// Sizes around the brick size (the last brick's extra block at offset 1 when the extent is a
/// multiple of 16), tiny and flat grids, and odd ones.
const std::vector<Int3> kEdgeSizes = {{16, 16, 16}, {32, 17, 15}, {1, 1, 1},  {2, 3, 1},   {47, 48, 49},
                                      {33, 1, 64},  {5, 80, 3},   {64, 64, 9}, {31, 33, 32}, {18, 14, 35}};

}  // namespace

TEST_CASE("cuda sparse: same hash as dense CPU stepping on random scenes, sizes, seeds and rule sets") {
  std::mt19937_64 rng(61061);
  std::vector<Int3> sizes = kEdgeSizes;
  for (int i = 0; i < 10; ++i) sizes.push_back(random_size(rng, 1, 90));
  int scene = 0;
  for (const Int3 size : sizes) {
    const char* rules = scene++ % 2 == 0 ? "paper" : "isotropic";
    const std::uint64_t seed = rng();
    CAPTURE(rules);
    CAPTURE(size.x);
    CAPTURE(size.y);
    CAPTURE(size.z);
    CAPTURE(seed);
    // Sand over a buried floor: most bricks fall asleep, the falling grains keep some awake.
    Grid initial = random_grid(size, rng(), int(rng() % 12), 5 + int(rng() % 30));
    for (int z = 0; z < size.z / 3; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
          if (initial.at({x, y, z}) == Material::Void) initial.set({x, y, z}, Material::Granular);
    Trio w(initial, rules, seed);
    REQUIRE(w.gpu.backend() == BackendKind::Cuda);
    for (const int ticks : {1, 7, 8, 3, 2, 16, 5, 100, 0, 9, 1, 1, 250, 31}) {
      CAPTURE(ticks);
      w.step(ticks);
      require_same(w);
    }
  }
}

TEST_CASE("cuda sparse: grids holding all 8 states match dense CPU stepping") {
  for (const char* rules : {"paper", "isotropic"}) {
    CAPTURE(rules);
    const Int3 size{45, 38, 50};
    Trio w(granular::test::random_grid_all_states(size, 31), rules, 6);
    for (const int ticks : {5, 8, 13, 64, 200}) {
      CAPTURE(ticks);
      w.step(ticks);
      require_same(w);
    }
  }
}

TEST_CASE("cuda sparse: a 128^3 bowl falls, piles and settles to zero active bricks, equal to dense CPU throughout") {
  for (const char* rules : {"paper", "isotropic"}) {
    CAPTURE(rules);
    const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), 128);
    Trio w(scene.grid, rules, 17);
    std::uint64_t done = 0;
    while (done < 8000) {
      w.step(500);
      done += 500;
      CAPTURE(done);
      require_same(w);
      if (w.gpu.activity().brick_ticks == 0) break;
    }
    if (std::string(rules) == "paper") CHECK(w.gpu.activity().active_bricks == 0);
    MESSAGE(rules << ": " << w.gpu.activity().active_bricks << " of " << w.gpu.activity().total_bricks
                  << " bricks active after " << done << " ticks");
  }
}

TEST_CASE("cuda sparse: tools between ticks wake the right bricks, on any tick of the cycle") {
  for (const char* rules : {"paper", "isotropic"}) {
    CAPTURE(rules);
    const Int3 size{80, 67, 48};
    Grid floor = random_grid(size, 4, 3, 0);
    for (int z = 0; z < 12; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
          if (floor.at({x, y, z}) == Material::Void) floor.set({x, y, z}, Material::Granular);
    Trio w(floor, rules, 1234);
    w.step(40);
    require_same(w);
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> ux(-3.0, size.x + 3.0), uy(-3.0, size.y + 3.0), uz(-3.0, size.z + 3.0);
    std::uniform_real_distribution<double> radius(1.0, 8.0);
    for (int round = 0; round < 40; ++round) {
      CAPTURE(round);
      const Vec3 c{ux(rng), uy(rng), uz(rng)};
      const double r = radius(rng);
      const std::int64_t amount = std::int64_t(rng() % 300);
      const Int3 lo{int(c.x), int(c.y), int(c.z)};
      const Box box{lo, {lo.x + 1 + int(rng() % 9), lo.y + 1 + int(rng() % 9), lo.z + 1 + int(rng() % 4)}};
      std::vector<std::optional<std::int64_t>> changed;
      w.each([&](World& world) {
        try {
          switch (round % 4) {
            case 0: changed.push_back(world.dig({c, r}).cells_changed); break;
            case 1: changed.push_back(world.pour(c, r, Material::Granular, amount).cells_changed); break;
            case 2: changed.push_back(world.paint(box, round % 8 == 2 ? Material::Solid : Material::Granular).cells_changed); break;
            default: changed.push_back(world.paint(Sphere{c, r}, Material::Void).cells_changed); break;
          }
        } catch (const InvalidArgument&) {
          changed.push_back(std::nullopt);
        }
      });
      CHECK(changed[0] == changed[1]);
      CHECK(changed[0] == changed[2]);
      const int ticks = int(rng() % 13);  // tools land on every tick of the cycle
      w.step(ticks);
      if (ticks > 0) require_same(w);
    }
    w.step(200);
    require_same(w);
  }
}

TEST_CASE("cuda sparse: bricks_changed_since and load() agree with the CPU") {
  const Int3 size{50, 35, 41};
  Trio w(random_grid(size, 21, 5, 15), "isotropic", 8);
  for (int call = 0; call < 40; ++call) {
    const std::uint64_t vc = w.cpu.change_version(), vg = w.gpu.change_version();
    w.step(1 + call % 5);
    require_same(w);
    CHECK(w.gpu.bricks_changed_since(vg) == w.cpu.bricks_changed_since(vc));
    if (call == 20) {
      const Grid other = random_grid(size, 5, 5, 25);
      w.each([&](World& world) { world.load(other); });
    }
  }
}

TEST_CASE("cuda sparse: a pour in one corner of a settled world keeps the rest asleep") {
  const Int3 size{256, 256, 96};
  Grid floor(size);
  for (int z = 0; z < 10; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) floor.set({x, y, z}, Material::Granular);
  World gpu(activity_def(BackendKind::Cuda, true, "isotropic", 3), floor);
  World dense(activity_def(BackendKind::Cpu, false, "isotropic", 3), floor);
  gpu.step(24);
  dense.step(24);
  REQUIRE(gpu.activity().active_bricks == 0);
  std::uint64_t most = 0;
  for (int t = 0; t < 300; ++t) {
    gpu.pour({20, 20, 80}, 4, Material::Granular, 8);
    dense.pour({20, 20, 80}, 4, Material::Granular, 8);
    gpu.step(1);
    dense.step(1);
    most = std::max(most, gpu.activity().active_bricks);
  }
  CHECK(gpu.hash() == dense.hash());
  CHECK(most > 0);
  CHECK(most <= 4 * 4 * 6);  // bricks x, y < 3 (heap), z < 6, and their neighbours
}
