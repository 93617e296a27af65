#include "renderers/cube_renderer.hpp"

#include <cstdint>
#include <vector>

#include "vulkan/barriers.hpp"
#include "cells/cell_buffer.hpp"
#include "granular/bricks.hpp"
#include "cells/material_palette.hpp"
#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

constexpr VkDeviceSize kInstancesPerBrick = 4096;

/// Throws a VulkanError suggesting the ray march when `bricks` instance slots or draw commands
/// exceed what this device allows.
std::uint32_t checked_bricks(const VulkanContext& context, std::uint32_t bricks) {
  VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties.pNext = &maintenance3;
  vkGetPhysicalDeviceProperties2(context.physical_device(), &properties);
  const VkPhysicalDeviceLimits& limits = properties.properties.limits;
  const VkDeviceSize instance_bytes = VkDeviceSize(bricks) * kInstancesPerBrick * 4;
  if (instance_bytes > limits.maxStorageBufferRange || instance_bytes > maintenance3.maxMemoryAllocationSize ||
      bricks > limits.maxDrawIndirectCount)
    throw VulkanError("the grid is too large for the instanced-cube renderer on " + context.device_name() +
                      " (instance buffer or draw count over the device's limits); use --renderer raymarch");
  return bricks;
}

}  // namespace


CubeRenderer::CubeRenderer(const VulkanContext& context, const CellBuffer& cells, const MaterialPalette& palette,
                           VkRenderPass target_pass)
    : BrickSurfaceRenderer(RendererKind::Cubes, context, cells, palette, target_pass,
                           storage_then_palette(4),  // cells, brick list, instances, draws; the palette at 4
                           {"cube.vert", "cube.frag", true}),
      instances_(context, checked_bricks(context, brick_total_) * kInstancesPerBrick * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 MemoryKind::DeviceLocal),
      draws_(context, 2 * VkDeviceSize(brick_total_) * sizeof(VkDrawIndirectCommand),
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
             MemoryKind::DeviceLocal),
      build_(context.device(), sets_.layout(), "cube_build.comp"),
      compaction_(context, draws_, brick_total_) {
  sets_.write_buffer(2, instances_.buffer());
  sets_.write_buffer(3, draws_.buffer());
  sets_.write_buffer(4, palette.buffer());
}

std::uint64_t CubeRenderer::prepare(VkCommandBuffer commands, const FrameView& view,
                                    std::span<const std::uint32_t> changed_bricks) {
  const std::uint32_t bricks = rebuild_.upload(view.slot, changed_bricks);
  if (bricks == 0) {
    compaction_.record(commands, view.raster, false);
    return 0;
  }
  // The previous frame's draw reads the instances and commands being rewritten.
  memory_barrier(commands, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                 VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  build_.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets_.set(view.slot));
  vkCmdPushConstants(commands, build_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(ViewConstants), &view.raster);
  vkCmdDispatch(commands, bricks, 1, 1);
  memory_barrier(commands, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  compaction_.record(commands, view.raster, true);
  return bricks;
}

}  // namespace viewer
