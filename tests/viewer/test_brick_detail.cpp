#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "cells/brick_detail.hpp"
#include "granular/bricks.hpp"
#include "renderers/offscreen_renderer.hpp"
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
  return grid_world(grid);
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
  // A threshold that makes some of the 64 bricks coarse and leaves others fine.
  float mixed = 0.0f;
  for (float t = 0.5f; t < 50.0f && mixed == 0.0f; t *= 1.1f) {
    BrickDetail detail({4, 4, 4}, t);
    std::vector<std::uint32_t> rebuild;
    detail.update(view_projection(camera), kHeight, rebuild);
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

TEST_CASE("marching cubes: bricks with more surface than their slots hold draw what fits, inside the grid's outline") {
  // Noise at 40% fill: more lattice edges cross the surface in a brick than its slot holds
  // vertices (as many as triangles, 3072). The build drops the triangles that would use a vertex
  // that found no room, and writes nothing past a slot: the image shows the noise, and nothing
  // outside the grid's outline.
  const granular::Int3 size{48, 48, 48};
  granular::Grid grid(size);
  std::uint32_t state = 12345u;
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        state = state * 1664525u + 1013904223u;
        if ((state >> 24) < 102u) grid.set({x, y, z}, granular::Material::Solid);
      }
  // The premise: brick (1, 1, 1) has more crossed lattice edges (vertices) than its 3072-vertex slot.
  const auto inside = [&](int x, int y, int z) {  // lattice point (x, y, z): 3 or more of its 8 cells filled
    int filled = 0;
    for (int c = 0; c < 8; ++c) {
      const granular::Int3 cell{x - 1 + (c & 1), y - 1 + (c >> 1 & 1), z - 1 + (c >> 2)};
      filled += grid.at(cell) != granular::Material::Void ? 1 : 0;
    }
    return filled * 0.125 > 0.35;
  };
  int crossed = 0;
  for (int z = 16; z <= 32; ++z)
    for (int y = 16; y <= 32; ++y)
      for (int x = 16; x <= 32; ++x) {
        if (x < 32 && inside(x, y, z) != inside(x + 1, y, z)) ++crossed;
        if (y < 32 && inside(x, y, z) != inside(x, y + 1, z)) ++crossed;
        if (z < 32 && inside(x, y, z) != inside(x, y, z + 1)) ++crossed;
      }
  REQUIRE(crossed > 3072);
  const auto world = grid_world(grid);
  const OrbitCamera camera = test_camera(size);
  const glm::mat4 to_clip = view_projection(camera);
  // The grid's outline: the bounding rectangle of its eight corners on the image, a pixel wider.
  float left = 1e9f, right = -1e9f, top = 1e9f, bottom = -1e9f;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec4 clip = to_clip * glm::vec4(float((corner & 1) * size.x), float((corner >> 1 & 1) * size.y),
                                                       float((corner >> 2) * size.z), 1.0f);
    const glm::vec2 at = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * glm::vec2(kWidth, kHeight);
    left = std::min(left, at.x - 1.0f);
    right = std::max(right, at.x + 1.0f);
    top = std::min(top, at.y - 1.0f);
    bottom = std::max(bottom, at.y + 1.0f);
  }
  const std::vector<std::uint8_t> image = marching_image(*world, camera, 0.0f);
  CHECK(coverage(image) > 0.1);
  int astray = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x)
      if (!is_background(pixel(image, x, y)) && (x < left || x > right || y < top || y > bottom)) ++astray;
  CHECK(astray == 0);
}
