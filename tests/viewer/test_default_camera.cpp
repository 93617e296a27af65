/// @file test_default_camera.cpp
/// The sandbox's default camera frames the scene's content (its non-void cells), so the pile and
/// the column fill the window rather than a corner of an empty grid.

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "session/content_framing.hpp"
#include "renderers/offscreen_renderer.hpp"
#include "session/scene_loader.hpp"
#include "viewer_test_support.hpp"

using namespace viewer;
using namespace viewer::test;

namespace {

/// The share of the image's width and height spanned by the pixels that are not background.
struct Span {
  double width = 0, height = 0;
};

Span content_span(const std::vector<std::uint8_t>& image, int width, int height) {
  int x0 = width, x1 = -1, y0 = height, y1 = -1;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4;
      if (is_background({image[i], image[i + 1], image[i + 2], image[i + 3]})) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (x1 < 0) return {};
  return {double(x1 - x0 + 1) / width, double(y1 - y0 + 1) / height};
}

SandboxWorld cpu_scene(const std::string& name) {
  WorldChoice choice;
  choice.scene = name;
  choice.backend = "cpu";
  choice.threads = 2;
  return load_world(choice);
}

}  // namespace

TEST_CASE("default camera: the content's bounds are the non-void cells, solids included") {
  const SandboxWorld column = cpu_scene("column");  // N = 64: floor 3 cells thick, the column 3..15 high
  const auto bounds = content_bounds(*column.world);
  REQUIRE(bounds);
  CHECK(bounds->min == granular::Int3{0, 0, 0});
  CHECK(bounds->max.x == 64);
  CHECK(bounds->max.y == 64);
  CHECK(bounds->max.z == 15);
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {32, 32, 32};
  granular::World world(def);
  CHECK_FALSE(content_bounds(world));
  world.paint(granular::Box{{5, 7, 9}, {6, 10, 20}}, granular::Material::Granular);
  CHECK(content_bounds(world) == granular::Box{{5, 7, 9}, {6, 10, 20}});
}

TEST_CASE("default camera: a headless render of pile and column at the sandbox's 16:9 is mostly content") {
  // 1280x720 (the sandbox's default size) at a quarter of the size.
  constexpr int width = 320, height = 180;
  for (const std::string scene : {"pile", "column"}) {
    CAPTURE(scene);
    SandboxWorld sandbox = cpu_scene(scene);
    const OrbitCamera camera = initial_camera("", *sandbox.world, float(width) / float(height));
    OffscreenRenderer renderer(context(), *sandbox.world, {std::uint32_t(width), std::uint32_t(height)}, RendererKind::Cubes);
    renderer.render(camera);
    const Span span = content_span(renderer.pixels(), width, height);
    MESSAGE(scene << ": content spans " << span.width * 100 << "% of the width, " << span.height * 100 << "% of the height");
    CHECK(std::max(span.width, span.height) >= 0.7);
    CHECK(span.width < 1.0);  // framed, not cut: a margin on both sides
    CHECK(span.height < 1.0);
  }
  CHECK(context().validation_messages() == 0);
}
