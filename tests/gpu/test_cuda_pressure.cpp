/// @file test_cuda_pressure.cpp
/// The pressure lever (MotionParams::pressure, preset inertial-24-pressure) and the momentum lever
/// on top of it (inertial-24-momentum: the side plane) on the CUDA backend: the device head field
/// (device_head_field.cuh), solved at the start of every tick, the wake of the bricks where a
/// pressure move may start, and the side plane stepped with the cells (walk_side_block) give the
/// CPU backend's cells and velocities bit for bit. The liquid
/// scenes u_tube and dam_break run on the CPU (dense and sparse) and on the GPU (dense, and sparse
/// with dense-recording ticks only and with sparse ticks only), with water painted and poured and a
/// hole dug between ticks; every world holds the dense CPU world's cells, the GPU's sparse worlds
/// report the sparse CPU world's activity figures, and the lever changes the outcome (the scenes
/// exercise it). Connected vessels at rest, one leg raised by a tool, show the wake: the far leg's
/// bricks, asleep and out of the tool's reach, wake only because their heads press.

#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "granular/cuda_options.hpp"
#include "granular/errors.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "gpu_worlds.hpp"

using namespace granular;
using granular::test::first_difference;
using granular::test::gpu_test_def;

namespace {

/// A WorldDef for `backend` (the CPU with 2 threads), dense or sparse, under `rules`, with the
/// given CUDA dense fractions (by default the motion model's).
WorldDef pressure_def(BackendKind backend, bool sparse, const char* rules, std::uint64_t seed,
                      double dense_fraction = CudaOptions{}.motion_dense_fraction) {
  return gpu_test_def(backend, sparse, rules, seed, dense_fraction);
}


/// The worlds compared, all from one grid under one rule set: [0] dense CPU (the reference),
/// [1] sparse CPU, [2] dense GPU, [3] sparse GPU with dense-recording ticks only (dense_fraction 0),
/// [4] sparse GPU with sparse ticks only (dense_fraction 1).
class PressureWorlds {
 public:
  /// The worlds of `initial` with `seed` under `rules` (a preset with the pressure lever).
  PressureWorlds(const Grid& initial, std::uint64_t seed, const char* rules = "inertial-24-pressure") {
    worlds_.emplace_back(pressure_def(BackendKind::Cpu, false, rules, seed), initial);
    worlds_.emplace_back(pressure_def(BackendKind::Cpu, true, rules, seed), initial);
    worlds_.emplace_back(pressure_def(BackendKind::Cuda, false, rules, seed), initial);
    worlds_.emplace_back(pressure_def(BackendKind::Cuda, true, rules, seed, 0.0), initial);
    worlds_.emplace_back(pressure_def(BackendKind::Cuda, true, rules, seed, 1.0), initial);
    for (std::size_t i = kDenseGpu; i < worlds_.size(); ++i) REQUIRE(worlds_[i].backend() == BackendKind::Cuda);
    REQUIRE(worlds_[kDenseGpu].rules().motion.pressure);
    counts_ = worlds_[0].count();
  }

  /// The dense CPU world.
  const World& reference() const { return worlds_[0]; }
  /// The dense GPU world.
  const World& dense_gpu() const { return worlds_[kDenseGpu]; }
  /// The sparse CPU world.
  const World& sparse_cpu() const { return worlds_[kSparseCpu]; }

  /// Steps every world `ticks` ticks; the counts are conserved and every world agrees.
  void step(int ticks) {
    CAPTURE(ticks);
    for (World& w : worlds_) w.step(ticks);
    CHECK(worlds_[0].count() == counts_);
    require_same();
  }

  /// Applies `tool` to every world, takes the new counts and checks that every world agrees.
  template <class Tool>
  void each(Tool&& tool) {
    for (World& w : worlds_) tool(w);
    counts_ = worlds_[0].count();
    require_same();
  }

 private:
  static constexpr std::size_t kSparseCpu = 1, kDenseGpu = 2, kFirstSparseGpu = 3;

  /// Every world against the dense CPU world (hash, the whole region, counts), and the sparse GPU
  /// worlds' activity figures against the sparse CPU world's.
  void require_same() const {
    const std::uint64_t reference = worlds_[0].hash();
    const Box whole{{0, 0, 0}, worlds_[0].size()};
    const std::vector<std::uint8_t> region = worlds_[0].read_region(whole);
    for (std::size_t i = 1; i < worlds_.size(); ++i) {
      CAPTURE(i);
      if (worlds_[i].hash() != reference) FAIL_CHECK(first_difference(worlds_[0], worlds_[i]));
      REQUIRE(worlds_[i].hash() == reference);
      CHECK(worlds_[i].read_region(whole) == region);
      CHECK(worlds_[i].count() == counts_);
    }
    const ActivityStats cpu = worlds_[kSparseCpu].activity();
    for (std::size_t i = kFirstSparseGpu; i < worlds_.size(); ++i) {
      CAPTURE(i);
      const ActivityStats gpu = worlds_[i].activity();
      CHECK(gpu.ticks == cpu.ticks);
      CHECK(gpu.active_bricks == cpu.active_bricks);
      CHECK(gpu.active_cells == cpu.active_cells);
      CHECK(gpu.brick_ticks == cpu.brick_ticks);
      CHECK(gpu.cell_ticks == cpu.cell_ticks);
    }
  }

  std::vector<World> worlds_;
  MaterialCounts counts_{};
};

/// Connected vessels at rest, 64 x 16 x 48 (4 x 1 x 3 bricks): a solid floor; a solid wall over
/// x = 16 .. 47 from z = 6 up, with a passage under it; water up to z = 10 everywhere below the
/// wall's top (the passage full, both legs level). Nothing moves until a tool raises a leg.
Grid level_vessels() {
  const Int3 size{64, 16, 48};
  Grid g(size);
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        Material m = Material::Void;
        if (z == 0 || (x >= 16 && x < 48 && z >= 6))
          m = Material::Solid;
        else if (z < 10)
          m = Material::Liquid;
        g.set({x, y, z}, m);
      }
  return g;
}

}  // namespace

TEST_CASE("cuda pressure: the liquid scenes under pressure, and under momentum, on the CPU and the GPU, dense and sparse, agree bit for bit") {
  struct Case {
    const char* scene;
    int n;
  };
  // u_tube at an odd N: odd extents (37 x 9 x 37), so coarse cells and bricks are cut at the far
  // edges; dam_break at 64 (64 x 16 x 40, 4 x 1 x 3 bricks).
  for (const std::string rules : {"inertial-24-pressure", "inertial-24-momentum"})
  for (const Case& c : {Case{"u_tube", 37}, Case{"dam_break", 64}})
    for (const std::uint64_t seed : {5u, 90001u}) {
      CAPTURE(rules);
      CAPTURE(c.scene);
      CAPTURE(seed);
      const SceneInstance instance = instantiate(load_scene(find_scene(c.scene)), c.n);
      PressureWorlds w(instance.grid, seed, rules.c_str());
      for (const int ticks : {1, 2, 5, 8, 13, 11}) w.step(ticks);
      // Under momentum the liquid moving now holds velocities on both backends (the plane is exercised).
      if (w.reference().rules().motion.momentum) CHECK(!w.dense_gpu().capture().side.empty());
      // The same scene without the lever: the lever moved something.
      World flow(pressure_def(BackendKind::Cpu, false, "inertial-24-flow", seed), instance.grid);
      flow.step(40);
      CHECK(flow.hash() != w.reference().hash());
      const Int3 s = w.reference().size();
      // Water painted high over the liquid, a hole dug into it, and water poured near the far side.
      w.each([&](World& world) { world.paint(Box{{2, 0, s.z - 6}, {s.x / 3, s.y, s.z - 3}}, Material::Liquid); });
      w.step(9);
      w.each([&](World& world) { world.dig(Sphere{{s.x * 0.2, s.y * 0.5, s.z * 0.25}, 3.5}); });
      w.step(17);
      w.each([&](World& world) { world.pour({s.x * 0.8, s.y * 0.5, s.z * 0.8}, 2.5, Material::Liquid, 40); });
      w.step(24);
      w.step(3);
    }
}

TEST_CASE("cuda pressure: a leg raised by a tool wakes the far leg's bricks through the heads, as on the CPU") {
  for (const std::uint64_t seed : {7u, 31337u}) {
    CAPTURE(seed);
    PressureWorlds w(level_vessels(), seed);
    // The level vessels come to rest: every brick asleep (the GPU's sparse worlds then still solve
    // the heads every tick).
    for (const int ticks : {1, 8, 15}) w.step(ticks);
    REQUIRE(w.sparse_cpu().activity().active_bricks == 0);
    // Water painted over the left leg (bricks x = 0; the paint wakes bricks x = 0 and 1): the right
    // leg (bricks x = 3) now lies under the left leg's head, and only the heads wake it.
    w.each([](World& world) { world.paint(Box{{0, 0, 10}, {16, 16, 36}}, Material::Liquid); });
    w.step(1);
    CHECK(w.sparse_cpu().activity().active_bricks > 6);
    for (const int ticks : {2, 5, 8, 24}) w.step(ticks);
  }
}

TEST_CASE("cuda momentum: auto picks the GPU, and a snapshot taken mid-burst continues bit for bit on the other backend") {
  const Grid g = instantiate(load_scene(find_scene("dam_break")), 32).grid;
  WorldDef def = gpu_test_def(BackendKind::Auto, true, "inertial-24-momentum", 3, 0.0);
  World gpu(def, g);
  REQUIRE(gpu.backend() == BackendKind::Cuda);
  gpu.step(6);
  const WorldSnapshot mid = gpu.capture();
  REQUIRE(!mid.side.empty());
  // The GPU's snapshot on the CPU, and the CPU's snapshot of the same tick back on a new GPU world.
  def.backend = BackendKind::Cpu;
  World cpu(def, mid);
  const WorldSnapshot mid_cpu = cpu.capture();
  CHECK(mid_cpu.side == mid.side);
  def.backend = BackendKind::Cuda;
  World gpu_again(def, mid_cpu);
  CHECK(gpu_again.hash() == gpu.hash());
  for (const int ticks : {1, 4, 9}) {
    gpu.step(ticks);
    cpu.step(ticks);
    gpu_again.step(ticks);
    CAPTURE(gpu.tick());
    if (cpu.hash() != gpu.hash()) FAIL_CHECK(first_difference(cpu, gpu));
    CHECK(cpu.hash() == gpu.hash());
    CHECK(gpu_again.hash() == gpu.hash());
  }
  // A tool gives the cells it changes velocity 0 on both backends; restore() puts the plane back.
  for (World* w : {&gpu, &cpu}) w->paint(Box{{0, 0, 0}, {12, 8, 12}}, Material::Void);
  CHECK(cpu.hash() == gpu.hash());
  CHECK(first_difference(cpu, gpu).empty());
  gpu.restore(mid);
  CHECK(gpu.capture().side == mid.side);
  CHECK(gpu.hash() == World(def, mid).hash());
}
