/// @file test_cuda_activity.cpp
/// Sparse stepping on the CUDA backend: the same grid as dense stepping on the CPU for any scene,
/// size, seed, rule set, step lengths and tools between ticks; and the same bookkeeping as the
/// CPU's sparse stepping (active bricks and cells per tick, changed bricks), which follows the same
/// sleep/wake rules, so every figure must agree exactly. Scenes of every material (liquids and gases
/// moving) run under every preset, with water and gas poured and painted between ticks. Every case runs the GPU world with
/// several WorldDef::cuda.dense_fraction values: 0 (every step() uses dense-recording ticks: the dense
/// kernels, fused pairs included, recording the sparse state), 1 (never: sparse ticks only), the
/// default (the backend switches by the awake fraction, so both kinds mix within cycles) and 0.5.

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "../reference/material_scenes.hpp"
#include "../test_support.hpp"
#include "fluid_tool_place.hpp"
#include "granular/errors.hpp"
#include "granular/rule_presets.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "gpu_worlds.hpp"

using namespace granular;
using granular::test::first_difference;
using granular::test::gpu_test_def;
using granular::test::random_grid;
using granular::test::random_size;

namespace {

/// The GPU worlds' WorldDef::cuda.dense_fraction (and motion_dense_fraction) values: always dense-recording, never, the default, half.
const std::array<double, 4> kFractions = {0.0, 1.0, CudaOptions{}.dense_fraction, 0.5};

/// A WorldDef for `backend` (the CPU with 2 threads), sparse or dense, with the given dense fractions.
WorldDef activity_def(BackendKind backend, bool sparse, const char* rules, std::uint64_t seed,
                      double dense_fraction = CudaOptions{}.dense_fraction) {
  return gpu_test_def(backend, sparse, rules, seed, dense_fraction);
}

/// The reference (dense CPU), the CPU's sparse stepping and the GPU's, one GPU world per fraction of
/// kFractions (gpus[i] has kFractions[i]), all from one grid.
struct Trio {
  World dense;
  World cpu;
  std::vector<World> gpus;
  Trio(const Grid& initial, const char* rules, std::uint64_t seed)
      : dense(activity_def(BackendKind::Cpu, false, rules, seed), initial),
        cpu(activity_def(BackendKind::Cpu, true, rules, seed), initial) {
    for (const double f : kFractions) gpus.emplace_back(activity_def(BackendKind::Cuda, true, rules, seed, f), initial);
  }
  /// Steps every world.
  void step(int ticks) {
    dense.step(ticks);
    cpu.step(ticks);
    for (World& g : gpus) g.step(ticks);
  }
  /// Applies `tool` to every world, in order: dense, cpu, then the GPU worlds.
  template <class Tool>
  void each(Tool&& tool) {
    tool(dense);
    tool(cpu);
    for (World& g : gpus) tool(g);
  }
};


/// Every sparse GPU world == dense CPU (cells), and its activity figures == the sparse CPU's.
void require_same(const Trio& w) {
  const std::uint64_t reference = w.dense.hash();
  REQUIRE(w.cpu.hash() == reference);
  const ActivityStats a = w.cpu.activity();
  for (std::size_t i = 0; i < w.gpus.size(); ++i) {
    INFO("gpu world with dense_fraction " << kFractions[i]);
    const World& g = w.gpus[i];
    const std::uint64_t gpu = g.hash();
    if (gpu != reference) FAIL_CHECK(first_difference(w.dense, g));
    REQUIRE(gpu == reference);
    const ActivityStats b = g.activity();
    CHECK(b.total_bricks == a.total_bricks);
    CHECK(b.ticks == a.ticks);
    CHECK(b.active_bricks == a.active_bricks);
    CHECK(b.active_cells == a.active_cells);
    CHECK(b.brick_ticks == a.brick_ticks);
    CHECK(b.cell_ticks == a.cell_ticks);
  }
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
    for (const World& g : w.gpus) REQUIRE(g.backend() == BackendKind::Cuda);
    for (const int ticks : {1, 7, 8, 3, 2, 16, 5, 100, 0, 9, 1, 1, 250, 31}) {
      CAPTURE(ticks);
      w.step(ticks);
      require_same(w);
    }
  }
}

TEST_CASE("cuda sparse: grids holding all 8 states match dense CPU stepping under every preset") {
  for (const std::string& rules : rule_preset_names()) {
    CAPTURE(rules);
    const Int3 size{45, 38, 50};
    Trio w(granular::test::random_grid_all_states(size, 31), rules.c_str(), 6);
    for (const int ticks : {5, 8, 13, 64}) {
      CAPTURE(ticks);
      w.step(ticks);
      require_same(w);
    }
    CHECK(w.gpus[0].count() == w.dense.count());
  }
}

TEST_CASE("cuda sparse: scenes of every material under every preset, water and gas poured and painted mid-run, match dense CPU stepping") {
  // Random scenes of void, solid, sand, water, gas, gravel and the static states 6, 7 (water on and
  // between grains, gas under it, falling grains and water above): liquids spread, gases rise and
  // spread under ceilings, sand and gravel sink through water, on odd extents and brick edges. Then
  // tools on random ticks of the cycle: water and gas poured into the air, a box painted with water,
  // a sphere with gas, and each world must still equal dense CPU stepping (sparse CPU and GPU, every
  // dense fraction) with the same activity figures.
  std::mt19937_64 rng(0xF1D);
  int scene = 0;
  for (const std::string& rules : rule_preset_names())
    for (const Int3 size : {Int3{41, 33, 37}, Int3{32, 17, 48}}) {
      const std::uint64_t scene_seed = rng(), seed = rng();
      CAPTURE(rules);
      CAPTURE(size.x);
      CAPTURE(size.y);
      CAPTURE(size.z);
      CAPTURE(seed);
      const Grid initial = granular::test::all_materials_scene(size, scene_seed);
      Trio w(initial, rules.c_str(), seed);
      for (const World& g : w.gpus) REQUIRE(g.backend() == BackendKind::Cuda);
      for (const int ticks : {1, 7, 8, 3}) {
        CAPTURE(ticks);
        w.step(ticks);
        require_same(w);
      }
      CHECK(w.gpus[0].count() == initial.count());  // every move is an exchange
      for (int round = 0; round < 8; ++round) {
        CAPTURE(round);
        const granular::test::FluidToolPlace place = granular::test::random_fluid_tool_place(rng, size);
        const Vec3 c = place.centre;
        const double r = place.radius;
        const std::int64_t amount = place.amount;
        const Box box = place.box;
        std::vector<std::optional<std::int64_t>> changed;
        w.each([&](World& world) {
          try {
            switch ((round + scene) % 4) {
              case 0: changed.push_back(world.pour(c, r, Material::Liquid, amount).cells_changed); break;
              case 1: changed.push_back(world.pour(c, r, Material::Gas, amount).cells_changed); break;
              case 2: changed.push_back(world.paint(box, Material::Liquid).cells_changed); break;
              default: changed.push_back(world.paint(Sphere{c, r}, Material::Gas).cells_changed); break;
            }
          } catch (const InvalidArgument&) {
            changed.push_back(std::nullopt);
          }
        });
        for (std::size_t i = 1; i < changed.size(); ++i) CHECK(changed[0] == changed[i]);
        const int ticks = 1 + int(rng() % 12);  // tools land on every tick of the cycle
        CAPTURE(ticks);
        w.step(ticks);
        require_same(w);
      }
      const MaterialCounts counts = w.dense.count();
      w.step(40);
      require_same(w);
      for (const World& g : w.gpus) CHECK(g.count() == counts);
      ++scene;
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
      if (w.cpu.activity().brick_ticks == 0) break;
    }
    if (std::string(rules) == "paper")
      for (const World& g : w.gpus) CHECK(g.activity().active_bricks == 0);
    MESSAGE(rules << ": " << w.gpus[0].activity().active_bricks << " of " << w.gpus[0].activity().total_bricks
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
      for (std::size_t i = 1; i < changed.size(); ++i) CHECK(changed[0] == changed[i]);
      const int ticks = int(rng() % 13);  // tools land on every tick of the cycle
      w.step(ticks);
      if (ticks > 0) require_same(w);
    }
    w.step(200);
    require_same(w);
  }
}

TEST_CASE("cuda sparse: bricks_changed_since and load() agree with the CPU") {
  for (const char* rules : {"isotropic", "paper"}) {
    CAPTURE(rules);
    const Int3 size{50, 35, 41};
    Trio w(random_grid(size, 21, 5, 15), rules, 8);
    for (int call = 0; call < 60; ++call) {
      CAPTURE(call);
      const std::uint64_t vc = w.cpu.change_version();
      std::vector<std::uint64_t> vg;
      for (const World& g : w.gpus) vg.push_back(g.change_version());
      w.step(1 + call % 5);
      require_same(w);
      const std::vector<std::uint32_t> expected = w.cpu.bricks_changed_since(vc);
      for (std::size_t i = 0; i < w.gpus.size(); ++i) {
        INFO("gpu world with dense_fraction " << kFractions[i]);
        CHECK(w.gpus[i].bricks_changed_since(vg[i]) == expected);
      }
      if (call == 20 || call == 41) {
        const Grid other = random_grid(size, 5 + std::uint64_t(call), 5, 25);
        w.each([&](World& world) { world.load(other); });
      }
    }
  }
}

TEST_CASE("cuda sparse: a pour in one corner of a settled world keeps the rest asleep") {
  const Int3 size{256, 256, 96};
  Grid floor(size);
  for (int z = 0; z < 10; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) floor.set({x, y, z}, Material::Granular);
  World dense(activity_def(BackendKind::Cpu, false, "isotropic", 3), floor);
  std::vector<World> gpus;
  for (const double f : kFractions) gpus.emplace_back(activity_def(BackendKind::Cuda, true, "isotropic", 3, f), floor);
  dense.step(24);
  for (World& gpu : gpus) {
    gpu.step(24);
    REQUIRE(gpu.activity().active_bricks == 0);
  }
  std::vector<std::uint64_t> most(gpus.size(), 0);
  for (int t = 0; t < 300; ++t) {
    dense.pour({20, 20, 80}, 4, Material::Granular, 8);
    dense.step(1);
    for (std::size_t i = 0; i < gpus.size(); ++i) {
      gpus[i].pour({20, 20, 80}, 4, Material::Granular, 8);
      gpus[i].step(1);
      most[i] = std::max(most[i], gpus[i].activity().active_bricks);
    }
  }
  for (std::size_t i = 0; i < gpus.size(); ++i) {
    INFO("gpu world with dense_fraction " << kFractions[i]);
    CHECK(gpus[i].hash() == dense.hash());
    CHECK(most[i] > 0);
    CHECK(most[i] <= 4 * 4 * 6);  // bricks x, y < 3 (heap), z < 6, and their neighbours
    CHECK(most[i] == most[0]);
  }
}

TEST_CASE("cuda sparse: long runs of random step lengths and parities, falling sand and tools, every fraction") {
  std::mt19937_64 rng(4242);
  for (const char* rules : {"isotropic", "paper"}) {
    CAPTURE(rules);
    const Int3 size{67, 52, 71};
    const std::uint64_t scene_seed = rng(), world_seed = rng();
    Trio w(random_grid(size, scene_seed, 6, 30), rules, world_seed);
    int done = 0;
    while (done < 1500) {
      const int ticks = 1 + int(rng() % 17);
      w.step(ticks);
      done += ticks;
      CAPTURE(done);
      require_same(w);
      if (rng() % 4 == 0) {
        const Vec3 c{double(rng() % 67), double(rng() % 52), 40.0 + double(rng() % 30)};
        w.each([&](World& world) { world.pour(c, 3.0, Material::Granular, 40); });
      }
    }
  }
}
