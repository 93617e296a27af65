#pragma once
/// @file device_image.hpp
/// 2D images in device-local memory and their views: the render target's colour and depth
/// images, the ray march's storage image.

#include <vulkan/vulkan.h>

namespace viewer {

class VulkanContext;

/// A 2D image, the device-local memory bound to it and, where its owner made one, a view of it;
/// destroy_device_image() frees them.
struct DeviceImage {
  VkImage image = VK_NULL_HANDLE;          ///< the image
  VkDeviceMemory memory = VK_NULL_HANDLE;  ///< its memory
  VkImageView view = VK_NULL_HANDLE;       ///< a view of it, or none
};

/// Creates a 2D image of `extent` and `format` (one mip level, one layer, one sample, optimal
/// tiling, undefined layout) for `usage`, bound to device-local memory; throws VulkanError.
DeviceImage create_device_image(const VulkanContext& context, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage);

/// Destroys the view, the image and the memory of `image` (those it has) and leaves it empty.
void destroy_device_image(VkDevice device, DeviceImage& image) noexcept;

/// Creates a 2D view of all of `image` (of `format`) for `aspect`; throws VulkanError.
VkImageView create_image_view(VkDevice device, VkImage image, VkFormat format, VkImageAspectFlags aspect);

}  // namespace viewer
