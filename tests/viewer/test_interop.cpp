#include <cstdint>
#include <doctest/doctest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "session/camera.hpp"
#include "granular/external_memory.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "interop_test_support.hpp"
#include "renderers/offscreen_renderer.hpp"
#include "cells/shared_cells.hpp"

namespace viewer::test {

VulkanContext& interop_context() {
  static VulkanContext context([] {
    ContextOptions options;
    // Validation on wherever the layer is installed (always in CI); a GPU machine without it says so.
    options.validation = validation_layer_available();
    if (!options.validation) std::fprintf(stderr, "notice: VK_LAYER_KHRONOS_validation not installed; running without validation\n");
    options.external_memory = true;
    options.device_uuid = *granular::cuda_device_uuid();
    return options;
  }());
  return context;
}

}  // namespace viewer::test

using namespace viewer;
using viewer::test::interop_context;

namespace {

constexpr VkExtent2D kExtent{320, 240};

std::unique_ptr<granular::World> bowl(granular::BackendKind backend, int n) {
  granular::WorldDef def;
  def.backend = backend;
  def.threads = 2;
  const granular::SceneInstance scene = granular::instantiate(granular::load_scene(granular::find_scene("bowl")), n);
  return std::make_unique<granular::World>(def, scene.grid);
}

double differing_fraction(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); i += 4)
    differing += (a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2]) ? 1 : 0;
  return double(differing) / double(a.size() / 4);
}

}  // namespace

TEST_CASE("interop: the shared-cells path renders the same pixels as the CPU-upload path") {
  for (RendererKind kind : {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch}) {
    CAPTURE(std::string(to_string(kind)));
    std::unique_ptr<SharedCells> shared;  // outlives the CUDA world below
    auto gpu_world = bowl(granular::BackendKind::Cuda, 64);
    auto cpu_world = bowl(granular::BackendKind::Cpu, 64);
    shared = std::make_unique<SharedCells>(interop_context(), *gpu_world);
    const OrbitCamera camera = OrbitCamera::framing(gpu_world->size());
    OffscreenRenderer through_interop(interop_context(), *gpu_world, kExtent, kind, shared.get());
    OffscreenRenderer through_upload(interop_context(), *cpu_world, kExtent, kind);
    for (int frame = 0; frame < 5; ++frame) {
      gpu_world->step(20);
      cpu_world->step(20);
      through_interop.render(camera);
      through_upload.render(camera);
    }
    REQUIRE(gpu_world->hash() == cpu_world->hash());
    CHECK(differing_fraction(through_interop.pixels(), through_upload.pixels()) < 0.001);
    through_interop.wait_idle();
    gpu_world.reset();
  }
  CHECK(interop_context().validation_messages() == 0);
}

TEST_CASE("interop: simulation and rendering overlap for many frames, every frame whole") {
  std::unique_ptr<SharedCells> shared;
  auto gpu_world = bowl(granular::BackendKind::Cuda, 128);
  auto cpu_world = bowl(granular::BackendKind::Cpu, 128);
  shared = std::make_unique<SharedCells>(interop_context(), *gpu_world);
  const OrbitCamera camera = OrbitCamera::framing(gpu_world->size());
  OffscreenRenderer renderer(interop_context(), *gpu_world, kExtent, RendererKind::Cubes, shared.get());
  OffscreenRenderer reference(interop_context(), *cpu_world, kExtent, RendererKind::Cubes);
  for (int frame = 1; frame <= 400; ++frame) {
    // step() returns at once; the next frame's snapshot waits for it on the device, and the step
    // after it waits on the device for the snapshot: the host never blocks.
    gpu_world->step(4);
    if (frame % 7 == 0) gpu_world->dig({{64, 64, 100}, 5.0});
    renderer.render(camera);
    cpu_world->step(4);
    if (frame % 7 == 0) cpu_world->dig({{64, 64, 100}, 5.0});
    if (frame % 100 == 0) {
      // A torn frame (cells read while CUDA wrote them) would differ from the CPU reference.
      reference.render(camera);
      CHECK(differing_fraction(renderer.pixels(), reference.pixels()) < 0.001);
    }
  }
  CHECK(gpu_world->hash() == cpu_world->hash());
  renderer.wait_idle();
  gpu_world.reset();
  CHECK(interop_context().validation_messages() == 0);
}
