/// @file test_cuda_bodies.cpp
/// Bodies (World::add_body) on the CUDA backend: ten bodies of every shape wandering through sand,
/// gravel, water and gas leave the same cells, the same reports and the same conserved counts on
/// the CPU and on CUDA, sparse and dense, tick after tick.

#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "granular/body.hpp"
#include "granular/world.hpp"
#include "gpu_worlds.hpp"

using namespace granular;
using granular::test::first_difference;
using granular::test::gpu_test_def;

namespace {

/// A bed of sand with gravel in it under water, gas above, and ten bodies; the same for every seed.
void bodies_scene(World& w, std::vector<BodyId>& ids) {
  w.paint(Box{{0, 0, 0}, {48, 48, 12}}, Material::Granular);
  w.paint(Box{{16, 16, 4}, {32, 32, 10}}, Material::Gravel);
  w.paint(Box{{0, 0, 12}, {48, 48, 20}}, Material::Liquid);
  w.pour({24, 24, 32}, 5, Material::Gas, 150);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < 10; ++i) {
    BodyDef def;
    def.shape = BodyShape(i % 3);
    def.half_extents = {2 + 2 * unit(rng), 2 + 2 * unit(rng), 2 + 2 * unit(rng)};
    def.radius = 2 + 2 * unit(rng);
    def.half_length = 1 + 2 * unit(rng);
    def.pose.position = {8 + 32 * unit(rng), 8 + 32 * unit(rng), 6 + 24 * unit(rng)};
    def.pose.orientation = {unit(rng), unit(rng), unit(rng), unit(rng)};
    def.pose.velocity = {unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5};
    def.pose.angular_velocity = {0.05 * unit(rng), 0.05 * unit(rng), 0.05 * unit(rng)};
    ids.push_back(w.add_body(def));
  }
}

}  // namespace

TEST_CASE("bodies: CPU and CUDA worlds hold the same cells and reports, sparse and dense") {
  for (const bool sparse : {true, false}) {
    CAPTURE(sparse);
    World cpu(gpu_test_def(BackendKind::Cpu, sparse, "inertial-24-flow", 3, 0.25));
    World gpu(gpu_test_def(BackendKind::Cuda, sparse, "inertial-24-flow", 3, 0.25));
    std::vector<BodyId> cpu_ids, gpu_ids;
    bodies_scene(cpu, cpu_ids);
    bodies_scene(gpu, gpu_ids);
    const MaterialCounts before = cpu.count();
    for (int t = 0; t < 120; ++t) {
      cpu.step(1);
      gpu.step(1);
      for (std::size_t i = 0; i < cpu_ids.size(); ++i) {
        const BodySand &a = cpu.body_sand(cpu_ids[i]), &b = gpu.body_sand(gpu_ids[i]);
        REQUIRE(a.cells == b.cells);
        REQUIRE(a.displaced == b.displaced);
        REQUIRE(a.force.z == b.force.z);
      }
      if (t % 20 == 19) {
        REQUIRE(first_difference(cpu, gpu) == "");
        REQUIRE(cpu.hash() == gpu.hash());
      }
    }
    const MaterialCounts after = gpu.count();
    for (int m = 1; m < 7; ++m) CHECK(after[std::size_t(m)] == before[std::size_t(m)]);
  }
}
