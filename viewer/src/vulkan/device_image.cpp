#include "vulkan/device_image.hpp"

#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {

DeviceImage create_device_image(const VulkanContext& context, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage) {
  const VkDevice device = context.device();
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  DeviceImage result;
  vk_check(vkCreateImage(device, &info, nullptr, &result.image), "vkCreateImage");
  try {
    VkMemoryRequirements requirements;
    vkGetImageMemoryRequirements(device, result.image, &requirements);
    VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex = context.memory_type(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    vk_check(vkAllocateMemory(device, &allocate, nullptr, &result.memory), "vkAllocateMemory (image)");
    vk_check(vkBindImageMemory(device, result.image, result.memory, 0), "vkBindImageMemory");
  } catch (...) {
    if (result.memory) vkFreeMemory(device, result.memory, nullptr);
    vkDestroyImage(device, result.image, nullptr);
    throw;
  }
  return result;
}

void destroy_device_image(VkDevice device, DeviceImage& image) noexcept {
  if (image.view) vkDestroyImageView(device, image.view, nullptr);
  if (image.image) vkDestroyImage(device, image.image, nullptr);
  if (image.memory) vkFreeMemory(device, image.memory, nullptr);
  image = DeviceImage{};
}

VkImageView create_image_view(VkDevice device, VkImage image, VkFormat format, VkImageAspectFlags aspect) {
  VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  info.image = image;
  info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  info.format = format;
  info.subresourceRange = {aspect, 0, 1, 0, 1};
  VkImageView view = VK_NULL_HANDLE;
  vk_check(vkCreateImageView(device, &info, nullptr, &view), "vkCreateImageView");
  return view;
}

}  // namespace viewer
