#pragma once
/// @file glfw_window.hpp
/// The sandbox window: GLFW initialisation (only in windowed mode), a window without a GL context,
/// the instance extensions Vulkan needs to present to it, and its surface.

#include <vulkan/vulkan.h>

#include <string>

#include "vulkan/vulkan_context.hpp"

struct GLFWwindow;

namespace viewer {

/// Initialises GLFW and opens a resizable window; terminates GLFW when destroyed.
class GlfwWindow {
 public:
  /// Opens a `width` x `height` window titled `title`. Throws VulkanError when there is no display
  /// or GLFW finds no Vulkan loader (the message suggests --headless).
  GlfwWindow(int width, int height, const std::string& title);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~GlfwWindow();
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  /// The GLFW handle.
  GLFWwindow* handle() const { return window_; }
  /// `options` with what a context that presents to this window needs: GLFW's instance extensions
  /// (added to those asked for) and the window's surface (the window must outlive the context).
  ContextOptions presenting(ContextOptions options) const;
  /// Framebuffer size in pixels (0 x 0 while minimised).
  VkExtent2D framebuffer_extent() const;
  /// True once the user asked to close it.
  bool should_close() const;

 private:
  VkSurfaceKHR create_surface(VkInstance instance) const;

  GLFWwindow* window_ = nullptr;
};

}  // namespace viewer
