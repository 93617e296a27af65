/// @file test_material_colours.cpp
/// Every renderer draws each material in the colour of the world's material table: a scene of
/// solid, sand, gravel, liquid and gas, with the presets' table and with a game's own table (an oil
/// in state 6, gravel recoloured). Opaque materials show their colour as lit from above; a liquid
/// or a gas moves the pixel from what lies behind it (the same scene without it) towards its own
/// colour, part of the way: it is seen through.

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "granular/raycast.hpp"
#include "granular/rule_presets.hpp"
#include "cells/material_palette.hpp"
#include "renderers/offscreen_renderer.hpp"
#include "session/png_writer.hpp"
#include "viewer_test_support.hpp"

using namespace viewer;
using namespace viewer::test;
using granular::Material;

namespace {

constexpr granular::Int3 kSize{64, 64, 48};

/// One block of material in the scene; the sampled pixel is the centre of its top face.
struct Block {
  Material material;
  granular::Box box;
};

/// A solid floor with a block of gravel, one of sand, a pool of liquid (on the floor) and a cloud
/// of gas (above it, in the corner furthest from the camera, so it hides nothing). The `extra`
/// state, when given, gets a pool of its own in the middle.
std::vector<Block> scene_blocks(std::optional<Material> extra) {
  std::vector<Block> blocks{
      {Material::Gravel, {{40, 4, 2}, {56, 20, 12}}},
      {Material::Granular, {{4, 40, 2}, {20, 56, 10}}},
      {Material::Liquid, {{36, 36, 2}, {60, 60, 6}}},
      {Material::Gas, {{4, 4, 14}, {24, 24, 24}}},
  };
  if (extra) blocks.push_back({*extra, {{26, 26, 2}, {34, 34, 5}}});
  return blocks;
}

/// The tests' camera, from higher up and closer, so that each block fills a patch of pixels.
OrbitCamera scene_camera() {
  OrbitCamera camera = test_camera(kSize);
  camera.pitch_degrees = 50;
  camera.distance *= 0.75f;
  return camera;
}

/// The scene on the CPU backend under `rules` (the default preset when null), without the blocks
/// of `left_out` (so a test sees what lies behind them).
std::unique_ptr<granular::World> scene_world(std::shared_ptr<const granular::RuleSet> rules, std::optional<Material> extra,
                                             std::optional<Material> left_out = std::nullopt) {
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.threads = 2;
  def.size = kSize;
  def.rule_set = std::move(rules);
  auto world = std::make_unique<granular::World>(def);
  world->paint(granular::Box{{0, 0, 0}, {kSize.x, kSize.y, 2}}, Material::Solid);
  for (const Block& block : scene_blocks(extra))
    if (block.material != left_out) world->paint(block.box, block.material);
  return world;
}

/// The pixel (top-left origin) where `point` (cells) appears.
glm::ivec2 project(const OrbitCamera& camera, glm::vec3 point) {
  const glm::vec4 clip = view_projection(camera) * glm::vec4(point, 1.0f);
  const glm::vec2 ndc = glm::vec2(clip) / clip.w;
  return glm::ivec2((ndc * 0.5f + 0.5f) * glm::vec2(kWidth, kHeight));
}

glm::vec3 top_centre(const granular::Box& box) {
  return {(box.min.x + box.max.x) * 0.5f, (box.min.y + box.max.y) * 0.5f, float(box.max.z)};
}

glm::vec3 rgb(Rgba c) { return {float(c.r), float(c.g), float(c.b)}; }

/// A table colour as a surface facing the sun's sky shows it: 0..255 per channel, times the
/// lighting of an upward face (0.72 * sun height + 0.38 sky, shading.glsl).
glm::vec3 lit_from_above(std::uint32_t colour) {
  const float sun_z = 0.84f / std::sqrt(0.45f * 0.45f + 0.30f * 0.30f + 0.84f * 0.84f);
  return colour_of(colour) * 255.0f * (0.72f * sun_z + 0.38f);
}

/// How far `seen` lies from `behind` towards `colour` (0: not at all, 1: the colour itself), and
/// how far (0..255 units) it strays from that line.
struct Blend {
  float fraction;
  float off_line;
};
Blend blend_of(glm::vec3 seen, glm::vec3 behind, glm::vec3 colour) {
  const glm::vec3 towards = colour - behind;
  const float fraction = glm::dot(seen - behind, towards) / glm::dot(towards, towards);
  return {fraction, glm::length(seen - (behind + fraction * towards))};
}

/// Writes `image` to $GRANULAR_VIEWER_TEST_IMAGES/<name>.png when that folder is set (to look at).
void keep_image(const std::vector<std::uint8_t>& image, const std::string& name) {
  if (const char* folder = std::getenv("GRANULAR_VIEWER_TEST_IMAGES"))
    write_png(std::string(folder) + "/" + name + ".png", kWidth, kHeight, image);
}

/// Renders the scene of `rules` with each renderer and checks every block's colour.
void check_scene_colours(const std::shared_ptr<const granular::RuleSet>& rules, std::optional<Material> extra,
                         const std::string& label) {
  auto world = scene_world(rules, extra);
  const granular::MaterialTable& table = world->rules().materials;
  const OrbitCamera camera = scene_camera();
  for (RendererKind kind : {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch}) {
    const std::string renderer = to_string(kind);
    CAPTURE(renderer);
    OffscreenRenderer offscreen(context(), *world, {kWidth, kHeight}, kind);
    offscreen.render(camera);
    const auto image = offscreen.pixels();
    keep_image(image, label + "-" + renderer);
    for (const Block& block : scene_blocks(extra)) {
      const granular::MaterialDef& def = table[granular::to_cell(block.material)];
      const std::string material = def.name;
      CAPTURE(material);
      const glm::ivec2 at = project(camera, top_centre(block.box) + glm::vec3(0.0f, 0.0f, -0.5f));
      // The pixel looks at the block: its ray's first non-void cell is of the block's material.
      const Ray ray = ray_through_pixel(camera, at.x + 0.5f, at.y + 0.5f, float(kWidth), float(kHeight));
      const auto hit = granular::raycast(*world, {ray.origin.x, ray.origin.y, ray.origin.z},
                                         {ray.direction.x, ray.direction.y, ray.direction.z});
      REQUIRE(hit);
      REQUIRE(hit->material == block.material);
      const glm::vec3 seen = rgb(pixel(image, at.x, at.y));
      const glm::vec3 expected = lit_from_above(def.colour);
      const MaterialLook look = look_of(def.behaviour);
      if (look == MaterialLook::Opaque) {
        // Its colour, within the per-cell brightness jitter (0.90..1.06).
        MESSAGE(label << " " << renderer << " " << material << ": pixel " << seen.r << " " << seen.g << " " << seen.b
                      << ", table colour lit " << expected.r << " " << expected.g << " " << expected.b);
        for (int c = 0; c < 3; ++c) {
          CHECK(seen[c] >= expected[c] * 0.88f - 4.0f);
          CHECK(seen[c] <= expected[c] * 1.08f + 4.0f);
        }
        continue;
      }
      // Seen through: between the same pixel without the block and the material's own colour.
      auto without = scene_world(rules, extra, block.material);
      OffscreenRenderer behind_renderer(context(), *without, {kWidth, kHeight}, kind);
      behind_renderer.render(camera);
      const glm::vec3 behind = rgb(pixel(behind_renderer.pixels(), at.x, at.y));
      const Blend blend = blend_of(seen, behind, expected);
      MESSAGE(label << " " << renderer << " " << material << ": pixel " << seen.r << " " << seen.g << " " << seen.b
                    << ", behind it " << behind.r << " " << behind.g << " " << behind.b << ": " << blend.fraction
                    << " of the way to the table colour, " << blend.off_line << " off the line");
      CHECK(glm::length(expected - behind) > 40.0f);  // the check can tell them apart
      if (look == MaterialLook::Liquid) {
        CHECK(blend.fraction > 0.4f);
        CHECK(blend.fraction < 0.95f);
      } else {
        CHECK(blend.fraction > 0.15f);
        CHECK(blend.fraction < 0.6f);
      }
      CHECK(blend.off_line < 30.0f);
    }
  }
  CHECK(context().validation_messages() == 0);
}

}  // namespace

TEST_CASE("material colours: the palette holds each state's table colour, look and whether it is static") {
  const granular::MaterialTable table = granular::preset("inertial-24").materials;
  const auto entries = palette_entries(table);
  for (int s = 0; s < granular::kMaterialCount; ++s) {
    CAPTURE(s);
    const std::uint32_t c = table[std::size_t(s)].colour;
    CHECK(entries[std::size_t(s)].colour.r == doctest::Approx(float(c >> 16) / 255.0f));
    CHECK(entries[std::size_t(s)].colour.g == doctest::Approx(float((c >> 8) & 0xFF) / 255.0f));
    CHECK(entries[std::size_t(s)].colour.b == doctest::Approx(float(c & 0xFF) / 255.0f));
    CHECK(entries[std::size_t(s)].look.x == std::uint32_t(look_of(table[std::size_t(s)].behaviour)));
    CHECK(entries[std::size_t(s)].look.y == (table[std::size_t(s)].behaviour == granular::Behaviour::Static ? 1u : 0u));
  }
  CHECK(look_of(granular::Behaviour::Void) == MaterialLook::Void);
  CHECK(look_of(granular::Behaviour::Static) == MaterialLook::Opaque);
  CHECK(look_of(granular::Behaviour::Granular) == MaterialLook::Opaque);
  CHECK(look_of(granular::Behaviour::Liquid) == MaterialLook::Liquid);
  CHECK(look_of(granular::Behaviour::Gas) == MaterialLook::Gas);
}

TEST_CASE("material colours: solid, sand, gravel, liquid and gas show their table colours in every renderer") {
  check_scene_colours(nullptr, std::nullopt, "presets");
}

TEST_CASE("material colours: a game's own table (an oil in state 6, gravel recoloured) shows in its colours") {
  granular::RuleSet rules = granular::preset("inertial-24");
  granular::MaterialDef& oil = rules.materials[6];
  oil = rules.materials[granular::to_cell(Material::Liquid)];
  oil.name = "oil";
  oil.colour = 0xE8B020;
  oil.density = 1;  // lighter than water
  rules.materials[granular::to_cell(Material::Gravel)].colour = 0xC040C0;
  check_scene_colours(std::make_shared<const granular::RuleSet>(rules), Material::State6, "game");
}
