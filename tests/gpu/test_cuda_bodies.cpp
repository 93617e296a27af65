/// @file test_cuda_bodies.cpp
/// Bodies (World::add_body) on the CUDA backend: ten bodies of every shape wandering through sand,
/// gravel, water and gas (tests/body_scene.hpp) leave the same cells, the same reports and the same
/// conserved counts on the CPU and on CUDA, sparse and dense, tick after tick; a CUDA world's
/// snapshot and undo hold its bodies.

#include <doctest/doctest.h>

#include <vector>

#include "body_scene.hpp"
#include "gpu_worlds.hpp"
#include "granular/body.hpp"
#include "granular/stroke_history.hpp"
#include "granular/world.hpp"

using namespace granular;
using granular::test::first_difference;
using granular::test::gpu_test_def;

TEST_CASE("bodies: CPU and CUDA worlds hold the same cells and reports, sparse and dense") {
  for (const bool sparse : {true, false}) {
    CAPTURE(sparse);
    World cpu(gpu_test_def(BackendKind::Cpu, sparse, "inertial-24-flow", 3, 0.25));
    World gpu(gpu_test_def(BackendKind::Cuda, sparse, "inertial-24-flow", 3, 0.25));
    test::WanderingBodies on_cpu(cpu), on_gpu(gpu);
    const std::vector<BodyId>& cpu_ids = on_cpu.ids;
    const std::vector<BodyId>& gpu_ids = on_gpu.ids;
    const MaterialCounts before = cpu.count();
    for (int t = 0; t < 120; ++t) {
      on_cpu.tick();
      on_gpu.tick();
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

TEST_CASE("bodies: a CUDA world's snapshot and undo hold its bodies; a CPU world made from the snapshot continues alike") {
  World gpu(gpu_test_def(BackendKind::Cuda, true, "inertial-24-flow", 3, 0.25));
  test::WanderingBodies scene(gpu);
  for (int t = 0; t < 40; ++t) scene.tick();
  const WorldSnapshot snapshot = gpu.capture();
  REQUIRE(snapshot.bodies.bodies.size() == scene.ids.size());
  World cpu(gpu_test_def(BackendKind::Cpu, true, "inertial-24-flow", 3, 0.25), snapshot);
  for (int t = 0; t < 40; ++t) {
    gpu.step(1);
    cpu.step(1);
  }
  REQUIRE(first_difference(cpu, gpu) == "");
  CHECK(cpu.hash() == gpu.hash());
  for (const BodyId id : scene.ids) CHECK(cpu.body_sand(id).force.z == gpu.body_sand(id).force.z);

  // An undo on CUDA puts the bodies back with the cells.
  StrokeHistory history(gpu);
  const std::uint64_t before = gpu.hash();
  history.begin_stroke();
  BodyDef crate;
  crate.pose.position = {20, 20, 30};
  crate.pose.velocity = {0, 0, -0.5};
  gpu.add_body(crate);
  history.end_stroke();
  for (int t = 0; t < 30; ++t) scene.tick();
  REQUIRE(history.undo().has_value());
  CHECK(gpu.hash() == before);
  CHECK(gpu.body_ids() == scene.ids);
}
