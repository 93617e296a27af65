#include "renderers/raymarch_renderer.hpp"

#include <cstdint>

#include "vulkan/barriers.hpp"
#include "vulkan/device_image.hpp"
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
  destroy_device_image(context_.device(), image_);
}

void RaymarchRenderer::ensure_image(VkExtent2D extent) {
  if (image_.image && extent.width == extent_.width && extent.height == extent_.height) return;
  // A new size only comes with a new render target, after the device went idle.
  release_image();
  extent_ = extent;
  image_ = create_device_image(context_, extent, VK_FORMAT_R8G8B8A8_UNORM,
                               VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  image_.view = create_image_view(context_.device(), image_.image, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_ASPECT_COLOR_BIT);
  sets_.write_storage_image(1, image_.view);
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
  transition_color_image(commands, image_.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
  march_.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets_.set(view.slot));
  vkCmdPushConstants(commands, march_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(ViewConstants), &view.inverse);
  vkCmdDispatch(commands, (view.extent.width + 7) / 8, (view.extent.height + 7) / 8, 1);
  transition_color_image(commands, image_.image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  transition_color_image(commands, view.target_image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {int(view.extent.width), int(view.extent.height), 1};
  blit.dstSubresource = blit.srcSubresource;
  blit.dstOffsets[1] = blit.srcOffsets[1];
  vkCmdBlitImage(commands, image_.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, view.target_image,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
  return bricks;
}

}  // namespace viewer
