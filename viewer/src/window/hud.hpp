#pragma once
/// @file hud.hpp
/// Dear ImGui over GLFW and Vulkan: context, backends, font upload, and drawing its frame into the
/// render pass. What the HUD shows is built by the caller between begin() and record().

#include <vulkan/vulkan.h>

#include <cstdint>

namespace viewer {

class VulkanContext;
class GlfwWindow;

/// The ImGui lifecycle for one window.
class Hud {
 public:
  /// Initialises ImGui for `window`, drawing in passes compatible with `render_pass`. Installs
  /// ImGui's GLFW callbacks, which chain to callbacks installed before.
  Hud(const VulkanContext& context, const GlfwWindow& window, VkRenderPass render_pass, std::uint32_t min_image_count,
      std::uint32_t image_count);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~Hud();
  Hud(const Hud&) = delete;
  Hud& operator=(const Hud&) = delete;

  /// Starts an ImGui frame.
  void begin();
  /// Ends the ImGui frame and records its draw into `commands` (inside the render pass).
  void record(VkCommandBuffer commands);
  /// Tells the backend the swapchain's new minimum image count.
  void set_min_image_count(std::uint32_t count);
  /// True while ImGui uses the mouse (over a window): the sandbox then ignores it.
  bool wants_mouse() const;
  /// True while ImGui uses the keyboard (a text field).
  bool wants_keyboard() const;

 private:
  VkDevice device_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  bool frame_open_ = false;
};

}  // namespace viewer
