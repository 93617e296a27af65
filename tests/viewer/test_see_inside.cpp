#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "renderers/offscreen_renderer.hpp"
#include "viewer_test_support.hpp"

using namespace viewer;
using namespace viewer::test;

namespace {

constexpr RendererKind kKinds[] = {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch};

/// A closed container full of sand: the scene, its N and a point inside the sand on the plane of
/// the section y:0.5 (cells).
struct Container {
  const char* scene;
  int n;
  glm::vec3 inside;
};

/// The hourglass's upper chamber (its body is closed at the top) and the silo's bin.
constexpr Container kContainers[] = {{"hourglass", 64, {16.0f, 16.0f, 44.0f}}, {"silo", 64, {32.0f, 32.0f, 40.0f}}};

/// The pixel (x, y) of a kWidth x kHeight image where `point` appears.
std::pair<int, int> pixel_of(const OrbitCamera& camera, glm::vec3 point) {
  const glm::vec4 clip = view_projection(camera) * glm::vec4(point, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return {int(std::lround((ndc.x + 1.0f) * 0.5f * kWidth - 0.5f)), int(std::lround((ndc.y + 1.0f) * 0.5f * kHeight - 0.5f))};
}

/// Sand's hue under any light: red above green above blue, blue well below red.
bool is_sandy(Rgba c) { return c.r > c.g && c.g > c.b && (c.r - c.b) * 3 > c.r; }

/// Sand seen through a translucent grey wall: a warm tint that neither the wall nor the sky has.
bool is_warm(Rgba c) { return c.r > c.g && c.g > c.b && c.r - c.b >= 12; }

/// The solid wall's grey (blue at least as strong as red, red and green alike), not the sky.
bool is_wall(Rgba c) { return std::abs(c.r - c.g) <= 10 && c.b + 2 >= c.r && !is_background(c); }

/// The fraction of the 7 x 7 pixels around `at` for which `test` holds.
double share_around(const std::vector<std::uint8_t>& image, std::pair<int, int> at, const std::function<bool(Rgba)>& test) {
  int hits = 0;
  for (int dy = -3; dy <= 3; ++dy)
    for (int dx = -3; dx <= 3; ++dx) hits += test(pixel(image, at.first + dx, at.second + dy)) ? 1 : 0;
  return hits / 49.0;
}

/// A view of the whole grid of `world` from the default angles, or from the opposite side.
OrbitCamera whole_grid(const granular::World& world, bool opposite = false) {
  OrbitCamera camera = OrbitCamera::framing(granular::Box{{0, 0, 0}, world.size()}, float(kWidth) / float(kHeight));
  if (opposite) camera.yaw_degrees += 180.0f;
  return camera;
}

std::vector<std::uint8_t> render_with(OffscreenRenderer& renderer, const OrbitCamera& camera, const SeeInside& inside) {
  renderer.world_renderer().set_see_inside(inside);
  renderer.render(camera);
  return renderer.pixels();
}

/// Through each of `sections`, the cubes and the ray march of `world` (the whole grid in view) differ
/// by more than 40 in some channel on less than `most_different` of the pixels (same cells, same
/// shading model: they differ only on edges), and the cubes cover more than 5% of the image.
void check_cubes_match_raymarch(const granular::World& world, std::initializer_list<const char*> sections,
                                double most_different) {
  const OrbitCamera camera = whole_grid(world);
  for (const char* section : sections) {
    CAPTURE(section);
    SeeInside inside;
    inside.section = parse_section(section);
    std::vector<std::vector<std::uint8_t>> images;
    for (RendererKind kind : {RendererKind::Cubes, RendererKind::Raymarch}) {
      OffscreenRenderer renderer(context(), world, {kWidth, kHeight}, kind);
      images.push_back(render_with(renderer, camera, inside));
    }
    CHECK(difference(images[0], images[1], 40) < most_different);
    CHECK(coverage(images[0]) > 0.05);
  }
  CHECK(context().validation_messages() == 0);
}

/// Runs `check` on each container's world with a renderer of each kind.
void for_each_container_and_renderer(
    const std::function<void(const Container&, const granular::World&, OffscreenRenderer&)>& check) {
  for (const Container& container : kContainers) {
    auto world = scene_world(container.scene, container.n);
    for (RendererKind kind : kKinds) {
      const std::string name = std::string(container.scene) + ", " + to_string(kind);
      CAPTURE(name);
      OffscreenRenderer renderer(context(), *world, {kWidth, kHeight}, kind);
      check(container, *world, renderer);
    }
  }
  CHECK(context().validation_messages() == 0);
}

SeeInside section_y_half() {
  SeeInside inside;
  inside.section = parse_section("y:0.5");
  return inside;
}

}  // namespace

TEST_CASE("see inside: the hourglass and the silo show their wall, and their sand through a section y:0.5 from either side") {
  for_each_container_and_renderer([](const Container& container, const granular::World& world, OffscreenRenderer& renderer) {
    for (bool opposite : {false, true}) {
      CAPTURE(opposite);
      const OrbitCamera camera = whole_grid(world, opposite);
      const std::pair<int, int> at = pixel_of(camera, container.inside);
      const auto closed = render_with(renderer, camera, {});
      CHECK(share_around(closed, at, is_wall) == 1.0);
      CHECK(share_around(closed, at, is_sandy) == 0.0);
      const auto cut = render_with(renderer, camera, section_y_half());
      CHECK(share_around(cut, at, is_sandy) == 1.0);
    }
  });
}

TEST_CASE("see inside: x-ray shows the sand through the hourglass's and the silo's walls") {
  SeeInside xray;
  xray.xray = true;
  for_each_container_and_renderer([&](const Container& container, const granular::World& world, OffscreenRenderer& renderer) {
    const OrbitCamera camera = whole_grid(world);
    const std::pair<int, int> at = pixel_of(camera, container.inside);
    CHECK(share_around(render_with(renderer, camera, {}), at, is_warm) == 0.0);
    CHECK(share_around(render_with(renderer, camera, xray), at, is_warm) == 1.0);
    CHECK(share_around(render_with(renderer, camera, {}), at, is_wall) == 1.0);  // and back
  });
}

TEST_CASE("see inside: moving the section rebuilds nothing; toggling x-ray rebuilds the bricks once") {
  auto world = scene_world("hourglass", 48);
  const OrbitCamera camera = whole_grid(*world);
  for (RendererKind kind : kKinds) {
    const std::string name = to_string(kind);
    CAPTURE(name);
    OffscreenRenderer renderer(context(), *world, {kWidth, kHeight}, kind);
    const std::uint64_t bricks = world->activity().total_bricks;
    CHECK(renderer.render(camera).bricks_rebuilt == bricks);
    SeeInside inside = section_y_half();
    for (int step = 0; step < 3; ++step) {
      renderer.world_renderer().set_see_inside(inside);
      CHECK(renderer.render(camera).bricks_rebuilt == 0);
      inside.section = inside.section.moved(-1).cycled();
    }
    inside.xray = true;
    renderer.world_renderer().set_see_inside(inside);
    CHECK(renderer.render(camera).bricks_rebuilt == bricks);
    CHECK(renderer.render(camera).bricks_rebuilt == 0);
  }
  CHECK(context().validation_messages() == 0);
}

TEST_CASE("see inside: through a section, the cubes and the ray march agree pixel for pixel") {
  auto world = scene_world("silo", 48);
  world->step(ticks_for_seconds(*world, 0.6));  // sand running out through the orifice
  check_cubes_match_raymarch(*world, {"x:0.5", "y:0.3", "z:0.6"}, 0.05);
}

TEST_CASE("see inside: a section cuts the cubes' merged face quads where it cuts the cells") {
  // A flat sand bed and a sand block on it: large rectangles of open faces on every axis
  // (cube_build.comp merges a row's open faces along the face's run axis, y for the x faces and x
  // for the others, and equal runs of the rows after it across). The x and y sections cut
  // rectangles along their run axis and across it; the z section cuts the x and y faces'
  // rectangles across and removes whole z-face rectangles.
  const granular::Int3 size{48, 48, 48};
  granular::Grid grid(size);
  grid.fill(granular::Box{{0, 0, 0}, {48, 48, 10}}, granular::Material::Granular);
  grid.fill(granular::Box{{12, 12, 10}, {36, 36, 30}}, granular::Material::Granular);
  check_cubes_match_raymarch(*grid_world(grid), {"x:0.5", "y:0.5", "z:0.4"}, 0.02);
}

TEST_CASE("see inside: bricks of scattered cells (more faces than a brick's slot) draw as cubes of cells") {
  // A checkerboard of sand: every grain shows six faces and none is open, so each brick has more
  // quads than its slot holds and cube_build.comp lists its cells instead.
  const granular::Int3 size{48, 48, 48};
  granular::Grid grid(size);
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        if ((x + y + z) % 2 == 0) grid.set({x, y, z}, granular::Material::Granular);
  check_cubes_match_raymarch(*grid_world(grid), {"x:0.5", "z:0.6"}, 0.05);
}
