#include "renderers/raymarch_renderer.hpp"

#include <cstdint>

#include "cells/cell_buffer.hpp"
#include "granular/bricks.hpp"
#include "vulkan/gpu_buffer.hpp"
#include "cells/material_palette.hpp"
#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {

RaymarchRenderer::RaymarchRenderer(const VulkanContext& context, const CellBuffer& cells, const MaterialPalette& palette)
    : context_(context),
      brick_counts_(granular::brick_counts(cells.size())),
      occupancy_(context, VkDeviceSize(brick_counts_.x) * brick_counts_.y * brick_counts_.z * 4,
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryKind::DeviceLocal),
      sets_(context.device(), {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                               VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                               VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER}),
      rebuild_(context, brick_counts_, sets_, 2),
      occupancy_pass_(context.device(), sets_.layout(), "brick_occupancy.comp"),
      march_(context.device(), sets_.layout(), "raymarch.comp") {
  sets_.write_buffer(0, cells.buffer());
  sets_.write_buffer(3, occupancy_.buffer());
  sets_.write_buffer(4, palette.buffer());
}

RaymarchRenderer::~RaymarchRenderer() { release_image(); }

void RaymarchRenderer::release_image() {
  const VkDevice device = context_.device();
  if (view_) vkDestroyImageView(device, view_, nullptr);
  if (image_) vkDestroyImage(device, image_, nullptr);
  if (memory_) vkFreeMemory(device, memory_, nullptr);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

void RaymarchRenderer::ensure_image(VkExtent2D extent) {
  if (image_ && extent.width == extent_.width && extent.height == extent_.height) return;
  // A new size only comes with a new render target, after the device went idle.
  release_image();
  extent_ = extent;
  const VkDevice device = context_.device();
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = VK_FORMAT_R8G8B8A8_UNORM;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  vk_check(vkCreateImage(device, &info, nullptr, &image_), "vkCreateImage (ray march)");
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device, image_, &requirements);
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = context_.memory_type(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  vk_check(vkAllocateMemory(device, &allocate, nullptr, &memory_), "vkAllocateMemory (ray march)");
  vk_check(vkBindImageMemory(device, image_, memory_, 0), "vkBindImageMemory (ray march)");
  VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view.image = image_;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = VK_FORMAT_R8G8B8A8_UNORM;
  view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vk_check(vkCreateImageView(device, &view, nullptr, &view_), "vkCreateImageView (ray march)");
  sets_.write_storage_image(1, view_);
}

std::uint64_t RaymarchRenderer::prepare(VkCommandBuffer commands, const FrameView& view,
                                        std::span<const std::uint32_t> changed_bricks) {
  ensure_image(view.extent);
  const std::uint32_t bricks = rebuild_.upload(view.slot, changed_bricks);
  if (bricks > 0) {
    memory_barrier(commands, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    occupancy_pass_.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets_.set(view.slot));
    vkCmdPushConstants(commands, occupancy_pass_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(ViewConstants), &view.raster);
    vkCmdDispatch(commands, bricks, 1, 1);
    memory_barrier(commands, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  }
  transition_color_image(commands, image_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
  march_.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets_.set(view.slot));
  vkCmdPushConstants(commands, march_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(ViewConstants), &view.inverse);
  vkCmdDispatch(commands, (view.extent.width + 7) / 8, (view.extent.height + 7) / 8, 1);
  transition_color_image(commands, image_, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  transition_color_image(commands, view.target_image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {int(view.extent.width), int(view.extent.height), 1};
  blit.dstSubresource = blit.srcSubresource;
  blit.dstOffsets[1] = blit.srcOffsets[1];
  vkCmdBlitImage(commands, image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, view.target_image,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
  return bricks;
}

}  // namespace viewer
