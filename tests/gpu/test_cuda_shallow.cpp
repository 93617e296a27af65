/// @file test_cuda_shallow.cpp
/// The shallow-water lever (MotionParams::shallow, preset inertial-24-shallow) on the CUDA backend:
/// the device face plane and pass (device_shallow_pass.cuh) give the CPU backend's cells and face
/// plane bit for bit, dense and sparse, through a dam break, a tool's splash and the rest that
/// follows, and through a U-tube's covered channel and a flow over a pipe; a world at rest then
/// costs no device work and stays at rest; a snapshot taken on one backend continues on the other.

#include <doctest/doctest.h>

#include <cstdint>
#include <string>

#include "granular/cuda_options.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "gpu_worlds.hpp"

using namespace granular;
using granular::test::first_difference;
using granular::test::gpu_test_def;

namespace {

constexpr const char* kShallow = "inertial-24-shallow";

/// A closed tank 96 long and 8 wide on a solid floor, a block of water 24 high over its first 24
/// columns.
Grid dam() {
  const Int3 s{96, 8, 30};
  Grid g(s);
  g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
  g.fill(Box{{0, 0, 1}, {24, s.y, 25}}, Material::Liquid);
  return g;
}

/// Pipes: a U-tube (legs of 8 x 8 over a channel 4 high under a wall 8 thick that reaches the
/// top, the left leg full 40 cells above it, the right empty) beside a floor with a tunnel full of
/// water under it, and a block of water that runs out over the tunnel's top.
Grid pipes() {
  const Int3 s{64, 8, 50};
  Grid g(s);
  g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
  g.fill(Box{{8, 0, 5}, {16, s.y, s.z}}, Material::Solid);
  g.fill(Box{{0, 0, 1}, {24, s.y, 5}}, Material::Liquid);
  g.fill(Box{{0, 0, 5}, {8, s.y, 45}}, Material::Liquid);
  g.fill(Box{{24, 0, 0}, {s.x, s.y, 8}}, Material::Solid);
  g.fill(Box{{36, 0, 2}, {52, s.y, 5}}, Material::Liquid);
  g.fill(Box{{24, 0, 8}, {32, s.y, 20}}, Material::Liquid);
  return g;
}

WorldDef def(BackendKind backend, bool sparse, double dense_fraction = CudaOptions{}.motion_dense_fraction) {
  WorldDef d = gpu_test_def(backend, sparse, kShallow, 0x5A11, dense_fraction);
  d.size = dam().size();
  return d;
}

}  // namespace

TEST_CASE("cuda shallow water: a dam break, a splash and the rest after it equal the CPU's, dense and sparse") {
  const Grid g = dam();
  World cpu(def(BackendKind::Cpu, true), g);
  World gpu_dense(def(BackendKind::Cuda, false), g);
  World gpu_sparse(def(BackendKind::Cuda, true, 0.0), g);  // sparse ticks only
  World gpu_recording(def(BackendKind::Cuda, true, 1.0), g);  // dense-recording ticks only
  REQUIRE(gpu_dense.backend() == BackendKind::Cuda);
  for (int round = 0; round < 24; ++round) {
    CAPTURE(round);
    const int ticks = 1 + round % 7;
    cpu.step(ticks);
    for (World* w : {&gpu_dense, &gpu_sparse, &gpu_recording}) {
      w->step(ticks);
      const std::string d = first_difference(cpu, *w);
      CHECK_MESSAGE(d.empty(), d);
      CHECK(w->hash() == cpu.hash());
    }
    if (round == 12)
      for (World* w : {&cpu, &gpu_dense, &gpu_sparse, &gpu_recording})
        w->pour(Vec3{70, 4, 20}, 3.0, Material::Liquid, 60);
  }
  CHECK_FALSE(cpu.capture().faces.empty());
  // On to rest: the same state on both, and then the GPU's sparse world steps nothing.
  for (int i = 0; i < 10; ++i) {
    cpu.step(50);
    gpu_sparse.step(50);
    CHECK(gpu_sparse.hash() == cpu.hash());
  }
  const std::uint64_t rest = cpu.hash();
  cpu.step(64);
  REQUIRE_MESSAGE(cpu.hash() == rest, "the dam break did not come to rest within 600 ticks");
  gpu_sparse.step(64);
  CHECK(gpu_sparse.hash() == rest);
  gpu_sparse.step(16);
  CHECK(gpu_sparse.activity().active_bricks == 0);
  CHECK(gpu_sparse.count() == cpu.count());
}

TEST_CASE("cuda shallow water: a snapshot taken mid-flow on one backend continues on the other") {
  const Grid g = dam();
  World cpu(def(BackendKind::Cpu, true), g);
  cpu.step(20);
  const WorldSnapshot s = cpu.capture();
  REQUIRE_FALSE(s.faces.empty());
  World gpu(def(BackendKind::Cuda, true), s);
  CHECK(gpu.hash() == cpu.hash());
  cpu.step(40);
  gpu.step(40);
  CHECK(gpu.hash() == cpu.hash());
  World back(def(BackendKind::Cpu, false), gpu.capture());
  back.step(25);
  cpu.step(25);
  CHECK(back.hash() == cpu.hash());
}

TEST_CASE("cuda shallow water: a U-tube through its covered channel and water over a pipe equal the CPU's, dense and sparse") {
  const Grid g = pipes();
  auto on = [&](BackendKind backend, bool sparse, double dense_fraction) {
    WorldDef d = def(backend, sparse, dense_fraction);
    d.size = g.size();
    return d;
  };
  World cpu(on(BackendKind::Cpu, true, CudaOptions{}.motion_dense_fraction), g);
  World gpu_dense(on(BackendKind::Cuda, false, CudaOptions{}.motion_dense_fraction), g);
  World gpu_sparse(on(BackendKind::Cuda, true, 0.0), g);
  REQUIRE(gpu_dense.backend() == BackendKind::Cuda);
  for (int round = 0; round < 16; ++round) {
    CAPTURE(round);
    const int ticks = 1 + round % 5;
    cpu.step(ticks);
    for (World* w : {&gpu_dense, &gpu_sparse}) {
      w->step(ticks);
      const std::string d = first_difference(cpu, *w);
      CHECK_MESSAGE(d.empty(), d);
      CHECK(w->hash() == cpu.hash());
    }
  }
  cpu.step(200);
  gpu_sparse.step(200);
  CHECK(gpu_sparse.hash() == cpu.hash());
  CHECK(gpu_sparse.count() == g.count());
}
