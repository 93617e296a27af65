#pragma once
/// @file viewer_test_support.hpp
/// What the viewer tests share: one validated Vulkan context for the whole run, the bowl world at a
/// small size, a fixed camera, and pixel statistics.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "session/camera.hpp"
#include "granular/world.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer::test {

/// Image size of the tests (small: lavapipe renders on two CPU cores in CI).
inline constexpr std::uint32_t kWidth = 320;
inline constexpr std::uint32_t kHeight = 240;

/// The process-wide context, with validation on.
VulkanContext& context();

/// A world of `grid`'s cells on the CPU backend (2 threads), under the default rules.
std::unique_ptr<granular::World> grid_world(const granular::Grid& grid);

/// Scene `scene` (a name from assets/scenes) at N = `n` on the CPU backend.
std::unique_ptr<granular::World> scene_world(const std::string& scene, int n);

/// The bowl scene at N = 64 on the CPU backend.
std::unique_ptr<granular::World> bowl_world(int n = 64);

/// Ticks of `world`'s rules that last `seconds` of simulated time (granular::tick_seconds, 5 mm
/// cells; at least 1), so that a test sees the same physical moment whatever the default rules.
int ticks_for_seconds(const granular::World& world, double seconds);

/// The fixed camera of the tests: the default framing of the grid.
OrbitCamera test_camera(granular::Int3 size);

/// Cells to clip space through `camera` for a kWidth x kHeight image (as the renderers draw it).
glm::mat4 view_projection(const OrbitCamera& camera);

/// RGBA of pixel (x, y).
struct Rgba {
  int r, g, b, a;
};
/// Pixel (x, y) of an RGBA8 image of kWidth x kHeight.
Rgba pixel(const std::vector<std::uint8_t>& image, int x, int y);
/// True when the colour is the background's (the clear colour, 0.62 0.72 0.84).
bool is_background(Rgba c);
/// True for a sandy colour: red > green > blue, clearly warm.
bool is_sand(Rgba c);
/// Fraction of pixels that are not background.
double coverage(const std::vector<std::uint8_t>& image);
/// Fraction of pixels whose colour differs by more than `tolerance` in some channel.
double difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int tolerance = 8);

}  // namespace viewer::test
