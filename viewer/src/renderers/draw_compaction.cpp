#include "renderers/draw_compaction.hpp"

#include <cmath>

#include "vulkan/barriers.hpp"
#include "granular/bricks.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {

namespace {

constexpr std::uint32_t kGroupSize = 256;

}  // namespace

DrawCompaction::DrawCompaction(const VulkanContext& context, const GpuBuffer& draws, std::uint32_t bricks,
                               const GpuBuffer* indices)
    : bricks_(bricks),
      indices_(indices),
      command_bytes_(std::uint32_t(indices ? sizeof(VkDrawIndexedIndirectCommand) : sizeof(VkDrawIndirectCommand))),
      groups_((bricks + kGroupSize - 1) / kGroupSize),
      compact_(context, 2 * VkDeviceSize(bricks) * command_bytes_,
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, MemoryKind::DeviceLocal),
      group_counts_(context, 2 * VkDeviceSize(groups_) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryKind::DeviceLocal),
      draw_counts_(context, 2 * 4,
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                   MemoryKind::DeviceLocal),
      sets_(context.device(), {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                               VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}),
      pass_(context.device(), sets_.layout(), "draw_compact.comp") {
  sets_.write_buffer(0, draws.buffer());
  sets_.write_buffer(1, compact_.buffer());
  sets_.write_buffer(2, group_counts_.buffer());
  sets_.write_buffer(3, draw_counts_.buffer());
  // Nothing drawn until the first compaction.
  context.run_once([&](VkCommandBuffer commands) { vkCmdFillBuffer(commands, draw_counts_.buffer(), 0, VK_WHOLE_SIZE, 0); });
}

void DrawCompaction::record(VkCommandBuffer commands, const ViewConstants& view, bool rebuilt) {
  const std::array<int, 3> eye_brick{int(std::floor(view.eye.x / granular::kBrickSize)),
                                     int(std::floor(view.eye.y / granular::kBrickSize)),
                                     int(std::floor(view.eye.z / granular::kBrickSize))};
  if (compacted_ && !rebuilt && eye_brick == eye_brick_) return;
  eye_brick_ = eye_brick;
  compacted_ = true;
  // Earlier frames' draws read the compacted lists being rewritten.
  memory_barrier(commands, VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  ViewConstants constants = view;
  constants.bricks.w = int(bricks_);
  constants.grid.x = int(command_bytes_ / 4);
  pass_.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets_.set(0));
  for (int pass = 0; pass < 2; ++pass) {
    constants.grid.w = pass;
    vkCmdPushConstants(commands, pass_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(constants), &constants);
    vkCmdDispatch(commands, 2 * groups_, 1, 1);
    memory_barrier(commands, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                   pass == 0 ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT : VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                   pass == 0 ? VK_ACCESS_2_SHADER_STORAGE_READ_BIT : VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
  }
}

void DrawCompaction::draw(VkCommandBuffer commands, int list) const {
  const VkDeviceSize offset = VkDeviceSize(list) * bricks_ * command_bytes_;
  if (indices_) {
    vkCmdBindIndexBuffer(commands, indices_->buffer(), 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexedIndirectCount(commands, compact_.buffer(), offset, draw_counts_.buffer(), VkDeviceSize(list) * 4, bricks_,
                                  command_bytes_);
  } else {
    vkCmdDrawIndirectCount(commands, compact_.buffer(), offset, draw_counts_.buffer(), VkDeviceSize(list) * 4, bricks_,
                           command_bytes_);
  }
}

}  // namespace viewer
