/// @file test_cuda_history.cpp
/// Snapshots and undo on the CUDA backend against the CPU: a snapshot taken on either backend
/// continues on the other with the same hashes; the device-side checkpoint gives the bricks as they
/// were; undo and redo of strokes put back the same worlds as on the CPU, sparse and dense, through
/// both ways World moves bricks (brick by brick and the whole grid at once).

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "../test_support.hpp"
#include "../tool_session.hpp"
#include "granular/stroke_history.hpp"
#include "granular/world.hpp"

using namespace granular;
using granular::test::fluid_scene;
using granular::test::play_alike;

namespace {

const Int3 kSize{72, 64, 80};

WorldDef history_def(BackendKind backend, bool sparse) {
  WorldDef def;
  def.backend = backend;
  def.sparse = sparse;
  def.threads = 2;
  def.seed = 11;
  return def;
}

/// One tick of the tool session on both worlds, requiring the same tick and hash.
void step_both(World& cpu, World& gpu) { play_alike(cpu, gpu, 1); }

}  // namespace

TEST_CASE("cuda history: a snapshot taken on one backend continues on the other with the same hashes") {
  for (const bool sparse : {true, false}) {
    CAPTURE(sparse);
    World gpu(history_def(BackendKind::Cuda, sparse), fluid_scene(kSize));
    World cpu(history_def(BackendKind::Cpu, sparse), fluid_scene(kSize));
    for (int i = 0; i < 30; ++i) step_both(cpu, gpu);
    const WorldSnapshot from_gpu = gpu.capture();
    CHECK(from_gpu.cells == cpu.capture().cells);
    World cpu_from_gpu(history_def(BackendKind::Cpu, sparse), from_gpu);
    World gpu_from_cpu(history_def(BackendKind::Cuda, sparse), cpu.capture());
    for (int i = 0; i < 40; ++i) {
      step_both(cpu, gpu);
      step_both(cpu_from_gpu, gpu_from_cpu);
      REQUIRE(cpu_from_gpu.hash() == cpu.hash());
    }
    gpu.restore(from_gpu);
    cpu.restore(from_gpu);
    for (int i = 0; i < 20; ++i) step_both(cpu, gpu);
  }
}

TEST_CASE("cuda history: the device checkpoint gives the bricks as they were when it was taken") {
  World gpu(history_def(BackendKind::Cuda, true), fluid_scene(kSize));
  gpu.step(5);
  std::vector<std::uint32_t> few = {0, 3, 17, 40}, all;
  const Int3 n = gpu.brick_counts();
  for (std::uint32_t b = 0; b < std::uint32_t(n.x * n.y * n.z); ++b) all.push_back(b);
  for (const auto* bricks : {&few, &all}) {  // brick by brick, and through one read of the whole grid
    std::vector<std::uint8_t> then(brick_cells(kSize, *bricks)), checkpoint(then.size());
    gpu.read_bricks(*bricks, then);
    gpu.take_checkpoint();
    CHECK(gpu.checkpoint_bytes() == std::uint64_t(kSize.x) * kSize.y * kSize.z);
    gpu.step(9);
    gpu.dig(Sphere{{8.0, 8.0, 20.0}, 10.0});
    gpu.read_checkpoint_bricks(*bricks, checkpoint);
    CHECK(checkpoint == then);
    gpu.drop_checkpoint();
    CHECK(gpu.checkpoint_bytes() == 0);
  }
}

TEST_CASE("cuda history: undo and redo of strokes give the CPU's worlds, sparse and dense") {
  for (const bool sparse : {true, false}) {
    CAPTURE(sparse);
    World gpu(history_def(BackendKind::Cuda, sparse), fluid_scene(kSize));
    World cpu(history_def(BackendKind::Cpu, sparse), fluid_scene(kSize));
    StrokeHistory gpu_history(gpu), cpu_history(cpu);
    std::vector<std::uint64_t> starts, ends;
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 6; ++i) step_both(cpu, gpu);
      starts.push_back(gpu.hash());
      gpu_history.begin_stroke();
      cpu_history.begin_stroke();
      for (int i = 0; i < 4; ++i) {
        for (World* w : {&cpu, &gpu}) w->dig(Sphere{{20.0 + 12 * k, 30.0, 40.0}, 6.0});
        step_both(cpu, gpu);
      }
      gpu_history.end_stroke();
      cpu_history.end_stroke();
      ends.push_back(gpu.hash());
    }
    for (int i = 0; i < 5; ++i) step_both(cpu, gpu);
    for (int k = 2; k >= 0; --k) {
      REQUIRE(gpu_history.undo());
      REQUIRE(cpu_history.undo());
      CHECK(gpu.hash() == starts[std::size_t(k)]);
      CHECK(cpu.hash() == gpu.hash());
      CHECK(cpu.tick() == gpu.tick());
    }
    for (int k = 0; k < 3; ++k) {
      REQUIRE(gpu_history.redo());
      REQUIRE(cpu_history.redo());
      CHECK(gpu.hash() == ends[std::size_t(k)]);
      CHECK(cpu.hash() == gpu.hash());
    }
    // After an undo both continue alike.
    REQUIRE(gpu_history.undo());
    REQUIRE(cpu_history.undo());
    for (int i = 0; i < 30; ++i) step_both(cpu, gpu);
  }
}
