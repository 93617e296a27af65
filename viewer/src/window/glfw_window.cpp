#include "window/glfw_window.hpp"

#include <cstdint>

#define GLFW_INCLUDE_NONE
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "vulkan/vulkan_check.hpp"

namespace viewer {
namespace {

std::string glfw_error() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}

}  // namespace

GlfwWindow::GlfwWindow(int width, int height, const std::string& title) {
  if (!glfwInit())
    throw VulkanError("cannot open a window (" + glfw_error() + "); is DISPLAY set? Without a display use --headless");
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw VulkanError("GLFW found no Vulkan loader; install libvulkan1 and a driver, or use --headless");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    const std::string why = glfw_error();
    glfwTerminate();
    throw VulkanError("cannot create the window: " + why);
  }
}

GlfwWindow::~GlfwWindow() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

ContextOptions GlfwWindow::presenting(ContextOptions options) const {
  std::uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  options.instance_extensions.insert(options.instance_extensions.end(), names, names + count);
  options.make_surface = [this](VkInstance instance) { return create_surface(instance); };
  return options;
}

VkSurfaceKHR GlfwWindow::create_surface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  vk_check(glfwCreateWindowSurface(instance, window_, nullptr, &surface), "glfwCreateWindowSurface");
  return surface;
}

VkExtent2D GlfwWindow::framebuffer_extent() const {
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  return {std::uint32_t(width), std::uint32_t(height)};
}

bool GlfwWindow::should_close() const { return glfwWindowShouldClose(window_); }

}  // namespace viewer
