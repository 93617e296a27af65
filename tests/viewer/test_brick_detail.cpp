#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "brick_detail.hpp"
#include "granular/activity.hpp"
#include "offscreen_renderer.hpp"
#include "viewer_test_support.hpp"

using namespace viewer;
using namespace viewer::test;

namespace {

constexpr std::uint32_t kImageHeight = 240;

/// A camera on the x axis through the centre of brick (0, 0, 0), `distance` cells from that
/// centre on its -x side, looking along +x.
glm::mat4 looking_along_x(float distance) {
  const glm::vec3 centre(8.0f);
  const glm::mat4 view = glm::lookAt(centre - glm::vec3(distance, 0.0f, 0.0f), centre, glm::vec3(0.0f, 0.0f, 1.0f));
  return glm::perspective(glm::radians(45.0f), 4.0f / 3.0f, 0.1f, 10000.0f) * view;
}

/// Pixels a cell covers at the point of brick (0, 0, 0) nearest that camera (its bounding sphere).
float nearest_cell_pixels(float distance) {
  return BrickDetail::cell_pixels(looking_along_x(distance), kImageHeight,
                                  distance - 0.5f * float(granular::kBrickSize) * std::sqrt(3.0f));
}

bool lists(const std::vector<std::uint32_t>& bricks, std::uint32_t brick) {
  return std::find(bricks.begin(), bricks.end(), brick) != bricks.end();
}

}  // namespace

TEST_CASE("brick detail: a brick turns coarse below the threshold, fine again only above 1.25 times it") {
  const float distance = 400.0f;
  const float pixels = nearest_cell_pixels(distance);
  REQUIRE(pixels > 0.5f);
  REQUIRE(pixels < 2.0f);
  // Just above the threshold: fine; nothing changes, nothing is rebuilt.
  BrickDetail fine({1, 1, 1}, pixels * 0.99f);
  std::vector<std::uint32_t> rebuild;
  CHECK_FALSE(fine.update(looking_along_x(distance), kImageHeight, rebuild));
  CHECK(fine.levels()[0] == BrickDetail::kFine);
  CHECK(rebuild.empty());
  // Just below it: coarse, and the brick is rebuilt.
  BrickDetail detail({1, 1, 1}, pixels * 1.01f);
  CHECK(detail.update(looking_along_x(distance), kImageHeight, rebuild));
  CHECK(detail.levels()[0] == BrickDetail::kCoarse);
  CHECK(rebuild == std::vector<std::uint32_t>{0});
  // The same view again changes nothing.
  rebuild.clear();
  CHECK_FALSE(detail.update(looking_along_x(distance), kImageHeight, rebuild));
  CHECK(rebuild.empty());
  // Nearer, so that a cell covers 1.2 times the threshold: still coarse (hysteresis).
  const float threshold = pixels * 1.01f;
  float nearer = distance;
  while (nearest_cell_pixels(nearer) < threshold * 1.2f) nearer -= 1.0f;
  CHECK_FALSE(detail.update(looking_along_x(nearer), kImageHeight, rebuild));
  CHECK(detail.levels()[0] == BrickDetail::kCoarse);
  // Nearer still, past 1.25 times the threshold: fine again.
  while (nearest_cell_pixels(nearer) <= threshold * BrickDetail::kHysteresis) nearer -= 1.0f;
  CHECK(detail.update(looking_along_x(nearer), kImageHeight, rebuild));
  CHECK(detail.levels()[0] == BrickDetail::kFine);
}

TEST_CASE("brick detail: far bricks go coarse, near ones stay fine, and a change rebuilds the face neighbours") {
  // Eight bricks in a row along the view: the first ones near, the last ones far.
  BrickDetail detail({8, 3, 1}, nearest_cell_pixels(200.0f));
  std::vector<std::uint32_t> rebuild;
  REQUIRE(detail.update(looking_along_x(100.0f), kImageHeight, rebuild));
  const auto level = [&](int x, int y) { return detail.levels()[std::size_t(x + 8 * y)]; };
  CHECK(level(0, 0) == BrickDetail::kFine);
  CHECK(level(7, 0) == BrickDetail::kCoarse);
  for (int x = 1; x < 8; ++x) CHECK(level(x, 0) >= level(x - 1, 0));
  // Every brick that turned coarse is listed, with its face neighbours in the grid (the fine brick
  // before the first coarse one of the row among them), but no brick two away from every change.
  int first_coarse = 0;
  while (level(first_coarse, 0) == BrickDetail::kFine) ++first_coarse;
  REQUIRE(first_coarse > 0);
  CHECK(lists(rebuild, std::uint32_t(first_coarse - 1)));
  for (std::uint32_t brick = 0; brick < 24; ++brick)
    if (detail.levels()[brick] == BrickDetail::kCoarse) CHECK(lists(rebuild, brick));
  if (first_coarse >= 2) CHECK_FALSE(lists(rebuild, std::uint32_t(first_coarse - 2)));
}

TEST_CASE("brick detail: a threshold of 0 keeps every brick fine") {
  BrickDetail detail({4, 4, 4}, 0.0f);
  std::vector<std::uint32_t> rebuild;
  CHECK_FALSE(detail.update(looking_along_x(5000.0f), kImageHeight, rebuild));
  CHECK(rebuild.empty());
  CHECK(std::all_of(detail.levels().begin(), detail.levels().end(), [](std::uint8_t l) { return l == BrickDetail::kFine; }));
}

namespace {

/// A floating slab of solid with a wavy top, over 4 x 4 x 4 bricks: through a crack in its
/// surface the sky shows (marching cubes culls back faces).
std::unique_ptr<granular::World> wavy_slab() {
  const granular::Int3 size{64, 64, 64};
  granular::Grid grid(size);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) {
      const int top = 30 + int(std::lround(6.0 * std::sin(x * 0.31) * std::cos(y * 0.23)));
      for (int z = 20; z < top; ++z) grid.set({x, y, z}, granular::Material::Solid);
    }
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.threads = 2;
  return std::make_unique<granular::World>(def, grid);
}

std::vector<std::uint8_t> marching_image(const granular::World& world, const OrbitCamera& camera, float coarse_below) {
  RenderDetail detail;
  detail.coarse_below_pixels = coarse_below;
  OffscreenRenderer renderer(context(), world, {kWidth, kHeight}, RendererKind::Marching, nullptr, detail);
  renderer.render(camera);
  return renderer.pixels();
}

/// True when the 3 x 3 pixels around (x, y) all show something of `image`.
bool covered_around(const std::vector<std::uint8_t>& image, int x, int y) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (is_background(pixel(image, x + dx, y + dy))) return false;
  return true;
}

}  // namespace

TEST_CASE("marching cubes: coarse bricks draw the surface fine ones draw, and no crack opens where levels meet") {
  const auto world = wavy_slab();
  const OrbitCamera camera = test_camera(world->size());
  const glm::mat4 view_projection = camera.projection(float(kWidth) / float(kHeight)) * camera.view();
  // A threshold that makes some of the 64 bricks coarse and leaves others fine.
  float mixed = 0.0f;
  for (float t = 0.5f; t < 50.0f && mixed == 0.0f; t *= 1.1f) {
    BrickDetail detail({4, 4, 4}, t);
    std::vector<std::uint32_t> rebuild;
    detail.update(view_projection, kHeight, rebuild);
    const auto coarse = std::count(detail.levels().begin(), detail.levels().end(), BrickDetail::kCoarse);
    if (coarse >= 20 && coarse <= 44) mixed = t;
  }
  REQUIRE(mixed > 0.0f);
  const std::vector<std::uint8_t> fine = marching_image(*world, camera, 0.0f);
  const std::vector<std::uint8_t> coarse = marching_image(*world, camera, 1000.0f);
  const std::vector<std::uint8_t> both = marching_image(*world, camera, mixed);
  CHECK(coverage(fine) > 0.2);
  // The same slab: its outline moves by at most a cell here and there.
  CHECK(std::abs(coverage(coarse) - coverage(fine)) < 0.01);
  CHECK(std::abs(coverage(both) - coverage(fine)) < 0.01);
  // Where the fine and the coarse slab both cover a pixel and its neighbours, the mixed one shows
  // no sky: its coarse bricks overlap their finer neighbours.
  int inside = 0, cracks = 0;
  for (int y = 1; y + 1 < int(kHeight); ++y)
    for (int x = 1; x + 1 < int(kWidth); ++x) {
      if (!covered_around(fine, x, y) || !covered_around(coarse, x, y)) continue;
      ++inside;
      if (is_background(pixel(both, x, y))) ++cracks;
    }
  CHECK(inside > int(kWidth * kHeight) / 5);
  CHECK(cracks == 0);
}
