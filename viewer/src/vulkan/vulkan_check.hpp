#pragma once
/// @file vulkan_check.hpp
/// The viewer's error type and the check applied to every VkResult.

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace viewer {

/// A Vulkan call failed or the machine lacks something the viewer needs; the message says which
/// call or feature and what to do.
class VulkanError : public std::runtime_error {
 public:
  /// Wraps `message`.
  explicit VulkanError(const std::string& message) : std::runtime_error(message) {}
};

/// The name of a VkResult ("VK_ERROR_OUT_OF_DEVICE_MEMORY").
const char* result_name(VkResult result);

/// Throws VulkanError naming `what` when `result` is an error code.
inline void vk_check(VkResult result, const char* what) {
  if (result < 0) throw VulkanError(std::string(what) + " failed: " + result_name(result));
}

}  // namespace viewer
