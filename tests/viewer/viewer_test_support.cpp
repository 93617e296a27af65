#include "viewer_test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "granular/scene.hpp"
#include "granular/time_scale.hpp"

namespace viewer::test {

VulkanContext& context() {
  static VulkanContext instance([] {
    ContextOptions options;
    // Validation on wherever the layer is installed (always in CI); a GPU machine without it says so.
    options.validation = validation_layer_available();
    if (!options.validation) std::fprintf(stderr, "notice: VK_LAYER_KHRONOS_validation not installed; running without validation\n");
    return options;
  }());
  return instance;
}

std::unique_ptr<granular::World> grid_world(const granular::Grid& grid) {
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.threads = 2;
  return std::make_unique<granular::World>(def, grid);
}

std::unique_ptr<granular::World> scene_world(const std::string& scene, int n) {
  return grid_world(granular::instantiate(granular::load_scene(granular::find_scene(scene)), n).grid);
}

std::unique_ptr<granular::World> bowl_world(int n) { return scene_world("bowl", n); }

int ticks_for_seconds(const granular::World& world, double seconds) {
  return std::max(1, int(std::lround(seconds / granular::tick_seconds(world.rules()))));
}

OrbitCamera test_camera(granular::Int3 size) { return OrbitCamera::framing(size); }

glm::mat4 view_projection(const OrbitCamera& camera) {
  return camera.projection(float(kWidth) / float(kHeight)) * camera.view();
}

Rgba pixel(const std::vector<std::uint8_t>& image, int x, int y) {
  const std::size_t i = (std::size_t(y) * kWidth + std::size_t(x)) * 4;
  return {image[i], image[i + 1], image[i + 2], image[i + 3]};
}

bool is_background(Rgba c) {
  return std::abs(c.r - 158) <= 2 && std::abs(c.g - 184) <= 2 && std::abs(c.b - 214) <= 2;
}

bool is_sand(Rgba c) { return c.r > c.g && c.g > c.b && c.r - c.b > 40; }

double coverage(const std::vector<std::uint8_t>& image) {
  std::size_t covered = 0;
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) covered += is_background(pixel(image, int(x), int(y))) ? 0 : 1;
  return double(covered) / double(kWidth * kHeight);
}

double difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int tolerance) {
  std::size_t differing = 0;
  for (std::size_t i = 0; i + 3 < a.size(); i += 4) {
    bool differs = false;
    for (int c = 0; c < 3; ++c) differs = differs || std::abs(int(a[i + c]) - int(b[i + c])) > tolerance;
    differing += differs ? 1 : 0;
  }
  return double(differing) / double(a.size() / 4);
}

}  // namespace viewer::test
