#include "renderers/marching_cubes_renderer.hpp"

#include <cstdint>
#include <algorithm>
#include <cstring>
#include <vector>

#include "vulkan/barriers.hpp"
#include "cells/brick_set.hpp"
#include "cells/cell_buffer.hpp"
#include "granular/bricks.hpp"
#include "renderers/marching_cubes_tables.hpp"
#include "cells/material_palette.hpp"
#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

constexpr VkDeviceSize kMaxTrianglesPerBrick = 3072;
constexpr VkDeviceSize kVertexBytes = 8;
constexpr VkDeviceSize kTriangleBytes = 3 * 4;  ///< three 32-bit indices

/// Triangles per brick slot, and vertices: 3072 (a rough surface through a brick needs ~1000
/// triangles and about half as many vertices), fewer when the index buffer would exceed what one
/// storage buffer or allocation may hold on this device.
std::uint32_t triangles_per_brick(const VulkanContext& context, std::uint32_t bricks) {
  VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties.pNext = &maintenance3;
  vkGetPhysicalDeviceProperties2(context.physical_device(), &properties);
  const VkDeviceSize limit =
      std::min<VkDeviceSize>(properties.properties.limits.maxStorageBufferRange, maintenance3.maxMemoryAllocationSize);
  const VkDeviceSize fitting = limit / (VkDeviceSize(bricks) * kTriangleBytes);
  if (fitting < 256)
    throw VulkanError("the grid is too large for the marching-cubes renderer on " + context.device_name() +
                      " (index buffer over the device's storage-buffer limit); use --renderer raymarch");
  return std::uint32_t(std::min(kMaxTrianglesPerBrick, fitting));
}

/// Invocations of a build workgroup: 64 on a CPU device (lavapipe runs a workgroup's invocations as
/// SIMD fibers that all meet at each barrier; 64 builds the 64³ bowl's bricks in 34-36 ms against
/// 42-43 with 256, bench/RESULTS.md), else the shader's 256.
std::uint32_t build_workgroup_size(const VulkanContext& context) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(context.physical_device(), &properties);
  return properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU ? 64 : 256;
}

/// The descriptor types of the classify, build and draw passes: cells, brick list, vertices, draws,
/// case table; the palette at 5; the brick levels at 6, the indices at 7, the mesh list at 8.
std::vector<VkDescriptorType> marching_bindings() {
  std::vector<VkDescriptorType> types = storage_then_palette(5);
  types.insert(types.end(), 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  return types;
}

/// The case table as the shader reads it: 256 x (edge count, 15 edges).
std::vector<std::uint32_t> gpu_case_table() {
  std::vector<std::uint32_t> table(256 * 16, 0);
  for (int mask = 0; mask < 256; ++mask) {
    const MarchingCase& c = marching_cases()[mask];
    table[mask * 16] = c.edge_count;
    for (std::uint32_t k = 0; k < c.edge_count; ++k) table[mask * 16 + 1 + k] = c.edges[k];
  }
  return table;
}


}  // namespace

MarchingCubesRenderer::MarchingCubesRenderer(const VulkanContext& context, const CellBuffer& cells,
                                             const MaterialPalette& palette, VkRenderPass target_pass,
                                             const RenderDetail& detail)
    : BrickSurfaceRenderer(RendererKind::Marching, context, cells, palette, target_pass, marching_bindings(),
                           {"mc.vert", "mc.frag", false}),
      triangles_per_brick_(triangles_per_brick(context, brick_total_)),
      vertices_(context, VkDeviceSize(brick_total_) * triangles_per_brick_ * kVertexBytes,
                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryKind::DeviceLocal),
      indices_(context, VkDeviceSize(brick_total_) * triangles_per_brick_ * kTriangleBytes,
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT, MemoryKind::DeviceLocal),
      draws_(context, 2 * VkDeviceSize(brick_total_) * sizeof(VkDrawIndexedIndirectCommand),
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, MemoryKind::DeviceLocal),
      mesh_list_(context, (3 + VkDeviceSize(brick_total_)) * 4,
                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                 MemoryKind::DeviceLocal),
      cases_(context, 256 * 16 * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
             MemoryKind::DeviceLocal),
      detail_(brick_counts_, detail.coarse_below_pixels),
      level_staging_(context, VK_BUFFER_USAGE_TRANSFER_SRC_BIT),
      levels_(context, (VkDeviceSize(brick_total_) + 3) / 4 * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
              MemoryKind::DeviceLocal),
      classify_(context.device(), sets_.layout(), "mc_classify.comp"),
      build_(context.device(), sets_.layout(), "mc_build.comp", build_workgroup_size(context)),
      compaction_(context, draws_, brick_total_, &indices_) {
  const std::vector<std::uint32_t> table = gpu_case_table();
  GpuBuffer staging(context, table.size() * 4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryKind::HostVisible);
  std::memcpy(staging.mapped(), table.data(), table.size() * 4);
  context.run_once([&](VkCommandBuffer commands) {
    const VkBufferCopy region{0, 0, table.size() * 4};
    vkCmdCopyBuffer(commands, staging.buffer(), cases_.buffer(), 1, &region);
    vkCmdFillBuffer(commands, levels_.buffer(), 0, VK_WHOLE_SIZE, 0);  // every brick fine, as detail_ starts
  });
  sets_.write_buffer(2, vertices_.buffer());
  sets_.write_buffer(3, draws_.buffer());
  sets_.write_buffer(4, cases_.buffer());
  sets_.write_buffer(5, palette.buffer());
  sets_.write_buffer(6, levels_.buffer());
  sets_.write_buffer(7, indices_.buffer());
  sets_.write_buffer(8, mesh_list_.buffer());
}

std::uint64_t MarchingCubesRenderer::prepare(VkCommandBuffer commands, const FrameView& view,
                                             std::span<const std::uint32_t> changed_bricks) {
  level_rebuild_.clear();
  std::vector<std::uint32_t> united_bricks;
  if (detail_.update(view.raster.matrix, view.extent.height, level_rebuild_)) {
    upload_levels(commands, view.slot);
    united_bricks = united(changed_bricks, level_rebuild_, brick_counts_);
    changed_bricks = united_bricks;
  }
  const std::uint32_t bricks = rebuild_.upload(view.slot, changed_bricks);
  if (bricks == 0) {
    compaction_.record(commands, view.raster, false);
    return 0;
  }
  // Earlier frames' draws and builds are done with what this frame's classify and build rewrite.
  memory_barrier(commands,
                 VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT |
                     VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_CLEAR_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
  // The mesh list's dispatch: no bricks yet, 1, 1.
  vkCmdFillBuffer(commands, mesh_list_.buffer(), 0, 4, 0);
  vkCmdFillBuffer(commands, mesh_list_.buffer(), 4, 8, 1);
  memory_barrier(commands, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  ViewConstants constants = view.raster;
  constants.bricks.w = int(triangles_per_brick_);
  classify_.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets_.set(view.slot));
  vkCmdPushConstants(commands, classify_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(constants), &constants);
  vkCmdDispatch(commands, bricks, 1, 1);
  memory_barrier(commands, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  build_.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets_.set(view.slot));
  vkCmdPushConstants(commands, build_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(constants), &constants);
  vkCmdDispatchIndirect(commands, mesh_list_.buffer(), 0);
  memory_barrier(commands, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT | VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT);
  compaction_.record(commands, view.raster, true);
  return bricks;
}

void MarchingCubesRenderer::upload_levels(VkCommandBuffer commands, int slot) {
  const std::span<const std::uint8_t> levels = detail_.levels();
  level_staging_.reserve(slot, levels_.size());
  std::memcpy(level_staging_.at(slot).mapped(), levels.data(), levels.size());
  // Earlier frames' builds read the levels before this copy overwrites them.
  memory_barrier(commands, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                 VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  const VkBufferCopy region{0, 0, levels.size()};
  vkCmdCopyBuffer(commands, level_staging_.at(slot).buffer(), levels_.buffer(), 1, &region);
  memory_barrier(commands, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

}  // namespace viewer
