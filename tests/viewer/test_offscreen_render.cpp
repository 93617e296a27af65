#include <cstdint>
#include <doctest/doctest.h>

#include <string>

#include "granular/raycast.hpp"
#include "renderers/offscreen_renderer.hpp"
#include "viewer_test_support.hpp"

using namespace viewer;
using namespace viewer::test;

namespace {

std::vector<std::uint8_t> render_once(OffscreenRenderer& renderer, const OrbitCamera& camera) {
  renderer.render(camera);
  return renderer.pixels();
}

}  // namespace

TEST_CASE("offscreen: the bowl scene renders, sand where the heap is, and changes after 0.4 s") {
  auto world = bowl_world();
  const OrbitCamera camera = test_camera(world->size());
  OffscreenRenderer renderer(context(), *world, {kWidth, kHeight}, RendererKind::Cubes);
  const auto start = render_once(renderer, camera);
  CHECK(coverage(start) > 0.25);
  CHECK(coverage(start) < 0.95);
  CHECK(is_sand(pixel(start, kWidth / 2, kHeight / 2)));  // the top of the sand block
  CHECK(is_background(pixel(start, 2, 2)));
  world->step(ticks_for_seconds(*world, 0.4));  // 100 ticks of the one-step rules
  const auto later = render_once(renderer, camera);
  CHECK(difference(start, later) > 0.05);
  CHECK(is_sand(pixel(later, kWidth / 2, kHeight / 2)));
  CHECK(context().validation_messages() == 0);
}

TEST_CASE("offscreen: digging along the camera's centre ray opens a hole in the next render") {
  auto world = bowl_world();
  world->step(ticks_for_seconds(*world, 0.16));
  const OrbitCamera camera = test_camera(world->size());
  OffscreenRenderer renderer(context(), *world, {kWidth, kHeight}, RendererKind::Cubes);
  const auto before = render_once(renderer, camera);
  const Ray ray = ray_through_pixel(camera, kWidth / 2.0f, kHeight / 2.0f, float(kWidth), float(kHeight));
  const auto hit = granular::raycast(*world, {ray.origin.x, ray.origin.y, ray.origin.z},
                                     {ray.direction.x, ray.direction.y, ray.direction.z});
  REQUIRE(hit);
  CHECK(hit->material == granular::Material::Granular);
  const granular::ChangeReport dug = world->dig({hit->point, 8.0});
  CHECK(dug.cells_changed > 500);
  const auto after = render_once(renderer, camera);
  // The centre pixel now sees deeper: still sand (the hole's floor) but shaded differently; the
  // pixels around the centre changed.
  int changed = 0;
  for (int y = int(kHeight) / 2 - 8; y <= int(kHeight) / 2 + 8; ++y)
    for (int x = int(kWidth) / 2 - 8; x <= int(kWidth) / 2 + 8; ++x) {
      const Rgba a = pixel(before, x, y), b = pixel(after, x, y);
      changed += (std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b)) > 12 ? 1 : 0;
    }
  CHECK(changed > 17 * 17 / 4);
  // The picked cell is void now, and a new ray through the centre goes deeper.
  CHECK(world->read_region(granular::Box{hit->cell, {hit->cell.x + 1, hit->cell.y + 1, hit->cell.z + 1}})[0] == 0);
  const auto deeper = granular::raycast(*world, {ray.origin.x, ray.origin.y, ray.origin.z},
                                        {ray.direction.x, ray.direction.y, ray.direction.z});
  REQUIRE(deeper);
  CHECK(deeper->distance > hit->distance + 3.0);
}

TEST_CASE("offscreen: every renderer draws the scene; cubes and ray march agree pixel for pixel") {
  auto world = bowl_world();
  world->step(ticks_for_seconds(*world, 0.48));
  const OrbitCamera camera = test_camera(world->size());
  std::vector<std::vector<std::uint8_t>> images;
  for (RendererKind kind : {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch}) {
    const std::string name = to_string(kind);
    CAPTURE(name);
    OffscreenRenderer renderer(context(), *world, {kWidth, kHeight}, kind);
    images.push_back(render_once(renderer, camera));
    CHECK(coverage(images.back()) > 0.25);
    CHECK(is_sand(pixel(images.back(), kWidth / 2, kHeight / 2)));
  }
  // Same cells, same shading model: the rasterised cubes and the ray march differ only on edges
  // and in the ambient-occlusion approximation.
  CHECK(difference(images[0], images[2], 40) < 0.05);
  CHECK(context().validation_messages() == 0);
}

TEST_CASE("offscreen: per-brick updates give the same image as uploading and rebuilding everything") {
  for (RendererKind kind : {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch}) {
    const std::string name = to_string(kind);
    CAPTURE(name);
    auto world = bowl_world(96);
    const OrbitCamera camera = test_camera(world->size());
    OffscreenRenderer incremental(context(), *world, {kWidth, kHeight}, kind);
    // With sparse stepping only the awake bricks change: a partial upload and rebuild each frame.
    for (int frame = 0; frame < 10; ++frame) {
      world->step(7);
      incremental.render(camera);
    }
    // Frames with only a tool call: only the bricks the tool touched are uploaded and rebuilt.
    const std::uint64_t total_bricks = world->activity().total_bricks;
    const auto surface = granular::raycast(*world, {30.5, 30.5, 500.0}, {0, 0, -1});
    REQUIRE(surface);
    const granular::Vec3 top = surface->point;
    const FrameWork dig = (world->dig({top, 6.0}), incremental.render(camera));
    const FrameWork pour = (world->pour({top.x, top.y, top.z + 4.0}, 3.0, granular::Material::Granular, 60),
                            incremental.render(camera));
    const FrameWork place = (world->paint(granular::Sphere{{60, 40, 60}, 4.0}, granular::Material::Solid), incremental.render(camera));
    for (const FrameWork& work : {dig, pour, place}) {
      CHECK(work.bricks_uploaded > 0);
      CHECK(work.bricks_uploaded < total_bricks / 2);
      CHECK(work.bricks_rebuilt < total_bricks);
    }
    const auto kept = incremental.pixels();
    OffscreenRenderer fresh(context(), *world, {kWidth, kHeight}, kind);
    const auto rebuilt = render_once(fresh, camera);
    CHECK(difference(kept, rebuilt, 2) < 0.001);
  }
  CHECK(context().validation_messages() == 0);
}

TEST_CASE("offscreen: switching renderers at run time rebuilds the new one from the current cells") {
  auto world = bowl_world(48);
  const OrbitCamera camera = test_camera(world->size());
  OffscreenRenderer renderer(context(), *world, {kWidth, kHeight}, RendererKind::Cubes);
  renderer.render(camera);
  renderer.set_kind(RendererKind::Marching);
  world->step(30);
  renderer.render(camera);
  renderer.set_kind(RendererKind::Cubes);  // the cube geometry is stale: it must be rebuilt
  world->step(30);
  const auto switched = render_once(renderer, camera);
  OffscreenRenderer fresh(context(), *world, {kWidth, kHeight}, RendererKind::Cubes);
  CHECK(difference(switched, render_once(fresh, camera), 2) < 0.001);
}
