/// @file test_material_panel.cpp
/// Under Xvfb: the HUD's material list offers every non-void state of the world's table on its
/// number key, a game's own materials included, and draws each one's colour swatch in the table's
/// colour (read back from the window's pixels).

#include <doctest/doctest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "session/camera.hpp"
#include "window/glfw_window.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "window/hud.hpp"
#include "session/material_choices.hpp"
#include "window/material_panel.hpp"
#include "session/png_writer.hpp"
#include "window/swapchain.hpp"
#include "vulkan/vulkan_context.hpp"
#include "renderers/world_renderer.hpp"

using namespace viewer;

namespace {

/// The presets' table with a game's own materials: an oil (liquid) in state 6, lava rock (static)
/// in state 7.
granular::RuleSet game_rules() {
  granular::RuleSet rules = granular::preset("inertial-24");
  granular::MaterialDef& oil = rules.materials[6];
  oil = rules.materials[granular::to_cell(granular::Material::Liquid)];
  oil.name = "oil";
  oil.colour = 0xE8B020;
  oil.density = 1;
  rules.materials[7].name = "lava rock";
  rules.materials[7].colour = 0xFF4010;
  return rules;
}

/// Pixels of the RGBA image `rgba` within 1 of `colour` (0xRRGGBB) in every channel.
int pixels_of_colour(const std::vector<std::uint8_t>& rgba, std::uint32_t colour) {
  const int r = int(colour >> 16), g = int((colour >> 8) & 0xFF), b = int(colour & 0xFF);
  int count = 0;
  for (std::size_t i = 0; i + 3 < rgba.size(); i += 4)
    count += (std::abs(rgba[i] - r) <= 1 && std::abs(rgba[i + 1] - g) <= 1 && std::abs(rgba[i + 2] - b) <= 1) ? 1 : 0;
  return count;
}

}  // namespace

TEST_CASE("material choices: every non-void state of the table on its number key, in order, static ones painted") {
  const granular::RuleSet rules = game_rules();
  const std::vector<MaterialChoice> choices = material_choices(rules.materials);
  REQUIRE(choices.size() == 7);
  const char* names[] = {"solid", "granular", "liquid", "gas", "gravel", "oil", "lava rock"};
  for (int key = 1; key <= 7; ++key) {
    CAPTURE(key);
    const auto choice = choice_of_key(choices, key);
    REQUIRE(choice);
    CHECK(int(choice->material) == key);
    CHECK(choice->name == names[key - 1]);
    CHECK(choice->colour == rules.materials[std::size_t(key)].colour);
    CHECK(choice->use == (rules.materials[std::size_t(key)].behaviour == granular::Behaviour::Static ? MaterialUse::Paint
                                                                                                    : MaterialUse::Pour));
  }
  CHECK_FALSE(choice_of_key(choices, 0));
  CHECK_FALSE(choice_of_key(choices, 8));
  CHECK(choice_of(choices, granular::Material::State6).name == "oil");
  const std::string listed = describe(choices);
  CHECK(listed.starts_with("1 solid #8C8C94, 2 granular #D9B873, "));
  CHECK(listed.ends_with(", 6 oil #E8B020, 7 lava rock #FF4010"));
}

TEST_CASE("material panel: the HUD shows a swatch of each material's table colour, a game's own included") {
  GlfwWindow window(640, 400, "material panel test");
  VulkanContext context(window.presenting({.validation = validation_layer_available()}));
  Swapchain swapchain(context, window.framebuffer_extent());
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {16, 16, 16};
  def.rule_set = std::make_shared<const granular::RuleSet>(game_rules());
  granular::World world(def);  // empty: only the background behind the HUD
  const std::vector<MaterialChoice> choices = material_choices(world.rules().materials);
  {
    Hud hud(context, window, swapchain.target().compatible_pass(), swapchain.min_image_count(), swapchain.image_count());
    WorldRenderer renderer(context, world, swapchain.target().compatible_pass(), RendererKind::Cubes);
    const OrbitCamera camera = OrbitCamera::framing(world.size());
    const granular::MaterialCounts counts = world.count();
    int drawn = 0;
    // A few frames: ImGui sizes a new window during its first frames.
    for (int i = 0; i < 20 && drawn < 4; ++i) {
      glfwPollEvents();
      const auto frame = swapchain.begin_frame();
      if (!frame) continue;
      hud.begin();
      ImGui::SetNextWindowPos(ImVec2(10, 10));
      ImGui::Begin("materials");
      draw_material_panel(choices, granular::Material::State6, counts);
      ImGui::End();
      renderer.record(frame->commands, frame->slot, swapchain.target(), frame->image_index, VK_IMAGE_LAYOUT_UNDEFINED,
                      camera, {}, [&](VkCommandBuffer commands) { hud.record(commands); });
      if (swapchain.end_frame(*frame)) ++drawn;
    }
    REQUIRE(drawn == 4);
    vkDeviceWaitIdle(context.device());
    const RenderTarget& target = swapchain.target();
    const std::vector<std::uint8_t> pixels =
        target.read_pixels(context, swapchain.last_presented(), VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
    if (const char* folder = std::getenv("GRANULAR_VIEWER_TEST_IMAGES"))
      write_png(std::string(folder) + "/material-panel.png", target.extent().width, target.extent().height, pixels);
    const int swatch_pixels = int((kSwatchSize - 2) * (kSwatchSize - 2));
    for (const MaterialChoice& choice : choices) {
      CAPTURE(choice.name);
      CHECK(pixels_of_colour(pixels, choice.colour) >= swatch_pixels);
    }
  }
  CHECK(context.validation_messages() == 0);
}
