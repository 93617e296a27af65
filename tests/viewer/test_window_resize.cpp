/// @file test_window_resize.cpp
/// Under Xvfb: a window's swapchain renders frames, is recreated after the window is resized, and
/// renders again at the new size, with the validation layer silent.

#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <memory>

#include "session/camera.hpp"
#include "window/glfw_window.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "window/swapchain.hpp"
#include "vulkan/vulkan_context.hpp"
#include "renderers/world_renderer.hpp"

using namespace viewer;

TEST_CASE("window: the swapchain follows a resize and keeps rendering") {
  GlfwWindow window(320, 240, "resize test");
  VulkanContext context(window.presenting({.validation = validation_layer_available()}));
  Swapchain swapchain(context, window.framebuffer_extent());
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  const granular::SceneInstance scene = granular::instantiate(granular::load_scene(granular::find_scene("pile")), 32);
  granular::World world(def, scene.grid);
  WorldRenderer renderer(context, world, swapchain.target().compatible_pass(), RendererKind::Cubes);
  const OrbitCamera camera = OrbitCamera::framing(world.size());
  auto draw_frames = [&](int count) {
    int drawn = 0;
    for (int i = 0; i < count * 4 && drawn < count; ++i) {
      glfwPollEvents();
      world.step(2);
      const auto frame = swapchain.begin_frame();
      if (!frame) {
        swapchain.recreate(window.framebuffer_extent());
        renderer.set_target_pass(swapchain.target().compatible_pass());
        continue;
      }
      renderer.record(frame->commands, frame->slot, swapchain.target(), frame->image_index, VK_IMAGE_LAYOUT_UNDEFINED,
                      camera, {});
      if (!swapchain.end_frame(*frame)) {
        swapchain.recreate(window.framebuffer_extent());
        renderer.set_target_pass(swapchain.target().compatible_pass());
      }
      ++drawn;
    }
    return drawn;
  };
  CHECK(draw_frames(3) == 3);
  glfwSetWindowSize(window.handle(), 400, 300);
  for (int i = 0; i < 20 && window.framebuffer_extent().width != 400; ++i) glfwWaitEventsTimeout(0.05);
  REQUIRE(window.framebuffer_extent().width == 400);
  swapchain.recreate(window.framebuffer_extent());
  renderer.set_target_pass(swapchain.target().compatible_pass());
  renderer.set_kind(RendererKind::Raymarch);  // a renderer created after the resize, on the new pass
  CHECK(draw_frames(3) == 3);
  CHECK(swapchain.target().extent().width == 400);
  CHECK(swapchain.target().extent().height == 300);
  vkDeviceWaitIdle(context.device());
  CHECK(context.validation_messages() == 0);
}
