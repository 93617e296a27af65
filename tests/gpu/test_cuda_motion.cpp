/// @file test_cuda_motion.cpp
/// The motion model (granular/motion.hpp) on the CUDA backend: the GPU-built motion table equals
/// the CPU's; the backend's dense and sparse motion kernels equal a plain host stepping of
/// motion::step_block over the raw bytes (motion levels included, grid edges, tools between
/// ticks; sand scenes and scenes of every material, the fluid pass included); and CPU and CUDA worlds of the inertial preset, dense and sparse, hold the same cells
/// bit for bit (hash and regions), the same, conserved, material counts and, sparse, the same
/// activity figures.

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "step/brick_grid.hpp"
#include "granular/errors.hpp"
#include "granular/extend/lut.hpp"
#include "granular/motion.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/world.hpp"
#include "gpu_worlds.hpp"
#include "granular_cuda/cuda_backend_factory.hpp"
#include "step/motion_block.hpp"
#include "step/step_materials.hpp"
#include "../reference/material_scenes.hpp"

using namespace granular;
using granular::test::first_difference;
using granular::test::gpu_test_def;

namespace {

/// The scenes' grid: odd extents, so that blocks straddle every edge at some offset.
constexpr Int3 kSceneSize{37, 29, 41};

/// A falling-block, pour and bowl-like scene: a solid floor and a sloped shelf, a solid pillar, a
/// block of sand in the air above the shelf's edge and loose grains sprinkled over the upper half.
Grid motion_scene(Int3 size, std::uint64_t seed) {
  Grid g(size);
  std::mt19937_64 rng(seed);
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        Material m = Material::Void;
        if (z == 0 || (x < size.x / 2 && z == 8 + x / 4) || (x >= 28 && x < 31 && y >= 10 && y < 13 && z < 20))
          m = Material::Solid;
        else if (x >= 12 && x < 24 && y >= 6 && y < 18 && z >= 24 && z < 32)
          m = Material::Granular;
        else if (z > size.z / 2 && rng() % 8 == 0)
          m = Material::Granular;
        g.set({x, y, z}, m);
      }
  return g;
}

/// One tick of the motion model on raw bytes (x fastest), every block of every sub-step stepped
/// with motion::step_block; cells outside the grid read as solid and are never written.
void reference_tick(std::vector<std::uint8_t>& cells, Int3 size, const RuleSet& rules, const Lut& lut,
                    std::uint64_t seed, std::uint64_t tick) {
  const auto load = [&](std::uint32_t index) {
    return motion::motion_entry_at(index, [&](std::uint32_t k) { return lut[motion::full_code_key(k)]; });
  };
  motion::SubStep sub = motion::sub_step(rules.motion, step_materials(rules.materials), seed, tick, 0, rules.random_symmetry);
  for (int s = 0; s < rules.motion.substeps; ++s) {
    sub.substep = s;
    const BlockOffset o = motion::motion_offset(tick, s, seed, rules.random_axis_order, rules.motion.momentum);
    for (int bz = 0; bz < block_count(size.z, o.z); ++bz)
      for (int by = 0; by < block_count(size.y, o.y); ++by)
        for (int bx = 0; bx < block_count(size.x, o.x); ++bx) {
          const int x0 = 2 * bx - o.x, y0 = 2 * by - o.y, z0 = 2 * bz - o.z;
          std::array<std::int64_t, 8> at{};
          std::uint64_t bytes = 0;
          for (int i = 0; i < 8; ++i) {
            const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + (i >> 2);
            const bool inside = x >= 0 && y >= 0 && z >= 0 && x < size.x && y < size.y && z < size.z;
            at[std::size_t(i)] = inside ? x + std::int64_t(size.x) * (y + std::int64_t(size.y) * z) : -1;
            bytes |= std::uint64_t(inside ? cells[std::size_t(at[std::size_t(i)])] : 1u) << (8 * i);
          }
          const std::uint64_t after = motion::step_block(bytes, sub, x0, y0, z0, load);
          for (int i = 0; i < 8; ++i)
            if (at[std::size_t(i)] >= 0) cells[std::size_t(at[std::size_t(i)])] = std::uint8_t(after >> (8 * i));
        }
  }
}

/// Writes `byte` into every cell of `box` on the backend and the reference, and wakes the box's
/// bricks (what World does after a tool).
void paint_raw(Backend& backend, std::vector<std::uint8_t>& reference, Int3 size, const Box& box, std::uint8_t byte) {
  const std::vector<std::uint8_t> fill(std::size_t(box.volume()), byte);
  std::vector<std::uint32_t> bricks;
  const Int3 counts = brick_counts(size);
  for (int z = box.min.z; z < box.max.z; ++z)
    for (int y = box.min.y; y < box.max.y; ++y)
      for (int x = box.min.x; x < box.max.x; ++x) {
        reference[std::size_t(x + std::int64_t(size.x) * (y + std::int64_t(size.y) * z))] = byte;
        bricks.push_back(brick_index(counts, brick_of(x), brick_of(y), brick_of(z)));
      }
  std::sort(bricks.begin(), bricks.end());
  bricks.erase(std::unique(bricks.begin(), bricks.end()), bricks.end());
  backend.write(box, fill, bricks);
}

/// Material counts of raw bytes (each byte's material bits).
MaterialCounts count_materials(const std::vector<std::uint8_t>& cells) {
  MaterialCounts counts{};
  for (const std::uint8_t c : cells) ++counts[cell_material(c)];
  return counts;
}

/// A WorldDef for `backend` (the CPU with 2 threads) under the inertial preset, sparse or dense.
WorldDef motion_def(BackendKind backend, bool sparse, std::uint64_t seed) {
  return gpu_test_def(backend, sparse, "inertial", seed, CudaOptions{}.motion_dense_fraction);
}


}  // namespace

TEST_CASE("cuda motion: the GPU-built motion table equals the CPU's Lut::build bit for bit") {
  const auto rules = make_rule_set("inertial");
  REQUIRE(rules->device_rule == "motion");
  const std::vector<Transition> gpu = build_lut_on_gpu(*rules);
  const Lut cpu = Lut::build(*rules, 0);
  REQUIRE(gpu.size() == cpu.entries().size());
  std::uint64_t mismatches = 0;
  for (std::size_t k = 0; k < gpu.size(); ++k) mismatches += gpu[k] != cpu.entries()[k] ? 1 : 0;
  CHECK(mismatches == 0);
}

TEST_CASE("cuda motion: dense and sparse motion kernels equal a host stepping of step_block") {
  for (const char* name : {"inertial", "inertial-24"}) {
    const auto rules = make_rule_set(name);
    REQUIRE(rules->motion.enabled());
    const auto lut = std::make_shared<const Lut>(Lut::build(*rules, 0));
    const StepMaterials mats = step_materials(rules->materials);
    for (const std::uint64_t seed : {1u, 77u, 4242u})
      for (const bool every_material : {false, true}) {
        CAPTURE(name);
        CAPTURE(seed);
        CAPTURE(every_material);
        // The sand scene, or one of every material (liquids spreading, gases rising, the fluid pass).
        Grid initial = every_material ? granular::test::all_materials_scene(kSceneSize, seed) : motion_scene(kSceneSize, seed);
        // Fallers (sand, gravel, water) already moving, at every level and phase, so that falls, rolls
        // and slow-downs occur at once.
        std::mt19937_64 rng(seed);
        for (auto& c : initial.cells())
          if (mats.is_faller(c)) {
            c = std::uint8_t(c | (rng() % std::uint64_t(rules->motion.max_level() + 1)) << kMotionShift);
            if (rng() % 2 == 0) c = std::uint8_t(c | kMotionPhaseBit);
          }
        std::vector<std::uint8_t> reference(initial.cells().begin(), initial.cells().end());
        const MaterialCounts counts = count_materials(reference);
        const auto dense =
            make_cuda_backend({.initial = initial, .lut = lut, .rules = rules, .seed = seed, .sparse = false});
        const auto sparse =
            make_cuda_backend({.initial = initial, .lut = lut, .rules = rules, .seed = seed, .sparse = true});
        std::uint64_t tick = 0;
        for (const int ticks : {1, 2, 5, 8, 13, 40, 3, 100}) {
          CAPTURE(ticks);
          for (int i = 0; i < ticks; ++i) reference_tick(reference, kSceneSize, *rules, *lut, seed, tick + std::uint64_t(i));
          dense->step(tick, ticks);
          sparse->step(tick, ticks);
          tick += std::uint64_t(ticks);
          const std::uint64_t expected = hash_cells(kSceneSize, reference);
          REQUIRE(dense->hash() == expected);
          REQUIRE(sparse->hash() == expected);
          CHECK(dense->count() == counts);
          CHECK(sparse->count() == counts);
          CHECK(sparse->last_activity().ticks == std::uint64_t(ticks));
        }
        // A tool between ticks: a slab of moving grains (level 2) dropped onto the settled scene; with
        // every material also a slab of moving water and one of gas low down.
        const std::uint8_t moving = std::uint8_t(to_cell(Material::Granular) | (2u << kMotionShift));
        paint_raw(*dense, reference, kSceneSize, Box{{3, 4, 33}, {30, 9, 36}}, moving);
        paint_raw(*sparse, reference, kSceneSize, Box{{3, 4, 33}, {30, 9, 36}}, moving);
        if (every_material) {
          const std::uint8_t water = std::uint8_t(to_cell(Material::Liquid) | (2u << kMotionShift));
          paint_raw(*dense, reference, kSceneSize, Box{{5, 12, 28}, {25, 20, 31}}, water);
          paint_raw(*sparse, reference, kSceneSize, Box{{5, 12, 28}, {25, 20, 31}}, water);
          paint_raw(*dense, reference, kSceneSize, Box{{10, 3, 2}, {20, 25, 4}}, to_cell(Material::Gas));
          paint_raw(*sparse, reference, kSceneSize, Box{{10, 3, 2}, {20, 25, 4}}, to_cell(Material::Gas));
        }
        for (int i = 0; i < 150; ++i) reference_tick(reference, kSceneSize, *rules, *lut, seed, tick + std::uint64_t(i));
        dense->step(tick, 150);
        sparse->step(tick, 150);
        const std::uint64_t expected = hash_cells(kSceneSize, reference);
        REQUIRE(dense->hash() == expected);
        REQUIRE(sparse->hash() == expected);
        std::vector<std::uint8_t> back(reference.size());
        sparse->read(Box{{0, 0, 0}, kSceneSize}, back);
        CHECK(back == reference);
        CHECK(sparse->count() == count_materials(reference));
      }
  }
}

TEST_CASE("cuda motion: inertial worlds on the CPU and the GPU, dense and sparse, agree bit for bit") {
  for (const std::uint64_t seed : {3u, 1009u, 65537u}) {
    CAPTURE(seed);
    const Grid initial = motion_scene(kSceneSize, seed);
    std::vector<World> worlds;
    for (const BackendKind backend : {BackendKind::Cpu, BackendKind::Cuda})
      for (const bool sparse : {false, true}) worlds.emplace_back(motion_def(backend, sparse, seed), initial);
    REQUIRE(worlds[2].backend() == BackendKind::Cuda);
    REQUIRE(worlds[2].rules().motion.enabled());
    MaterialCounts counts = worlds[0].count();
    // Checks every world against the first (dense CPU): hash, the whole region, counts; and the
    // sparse GPU world's activity figures against the sparse CPU world's.
    auto require_same = [&] {
      const std::uint64_t reference = worlds[0].hash();
      const Box whole{{0, 0, 0}, kSceneSize};
      const std::vector<std::uint8_t> region = worlds[0].read_region(whole);
      for (std::size_t i = 1; i < worlds.size(); ++i) {
        CAPTURE(i);
        if (worlds[i].hash() != reference) FAIL_CHECK(first_difference(worlds[0], worlds[i]));
        REQUIRE(worlds[i].hash() == reference);
        CHECK(worlds[i].read_region(whole) == region);
        CHECK(worlds[i].count() == counts);
      }
      const ActivityStats cpu = worlds[1].activity(), gpu = worlds[3].activity();
      CHECK(gpu.ticks == cpu.ticks);
      CHECK(gpu.active_bricks == cpu.active_bricks);
      CHECK(gpu.active_cells == cpu.active_cells);
      CHECK(gpu.brick_ticks == cpu.brick_ticks);
      CHECK(gpu.cell_ticks == cpu.cell_ticks);
    };
    // Steps every world; the counts are conserved.
    auto step = [&](int ticks) {
      CAPTURE(ticks);
      for (World& w : worlds) w.step(ticks);
      CHECK(worlds[0].count() == counts);
      require_same();
    };
    // Applies a tool to every world and takes the new counts.
    auto each = [&](auto&& tool) {
      for (World& w : worlds) tool(w);
      counts = worlds[0].count();
      require_same();
    };
    for (const int ticks : {1, 7, 8, 3, 30}) step(ticks);
    each([](World& w) { w.dig(Sphere{{18, 14, 12}, 5.5}); });
    step(25);
    each([](World& w) { w.pour({9, 20, 36}, 3.5, Material::Granular, 60); });
    step(9);
    step(40);
    each([](World& w) { w.paint(Box{{20, 2, 30}, {33, 8, 34}}, Material::Granular); });
    step(17);
    each([](World& w) { w.paint(Sphere{{10, 10, 10}, 4}, Material::Solid); });
    step(100);
    each([](World& w) { w.pour({30, 22, 38}, 2.5, Material::Granular, 25); });
    step(64);
  }
}
