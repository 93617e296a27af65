#include "cells/cell_buffer.hpp"

#include <cstdint>
#include <cstring>
#include <vector>

#include "vulkan/barriers.hpp"
#include "granular/bricks.hpp"
#include "granular/world.hpp"
#include "vulkan/pipeline_builder.hpp"
#include "renderers/view_constants.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

constexpr VkDeviceSize kBrickCells = VkDeviceSize(granular::kBrickSize) * granular::kBrickSize * granular::kBrickSize;

VkDeviceSize cell_bytes(granular::Int3 size) {
  return (VkDeviceSize(size.x) * size.y * size.z + 3) / 4 * 4;
}

/// Earlier readers of the cells (build passes, vertex shaders, ray march) finish before a write.
void wait_for_readers(VkCommandBuffer commands) {
  memory_barrier(commands, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                 VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

/// The written cells become visible to every later shader read.
void release_to_readers(VkCommandBuffer commands) {
  memory_barrier(commands, VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

}  // namespace

CellBuffer::CellBuffer(const VulkanContext& context, granular::Int3 size)
    : context_(context),
      size_(size),
      cells_(context, cell_bytes(size),
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
             MemoryKind::DeviceLocal),
      staging_(context, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
      brick_lists_(context, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT),
      gather_lists_(context, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT) {
  scatter_sets_ = std::make_unique<DescriptorSets>(
      context.device(), std::vector<VkDescriptorType>(3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER));
  scatter_sets_->write_buffer(0, cells_.buffer());
  scatter_ = std::make_unique<Pipeline>(context.device(), scatter_sets_->layout(), "cell_scatter.comp");
  gather_sets_ = std::make_unique<DescriptorSets>(
      context.device(), std::vector<VkDescriptorType>(3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER));
  gather_sets_->write_buffer(0, cells_.buffer());
  gather_ = std::make_unique<Pipeline>(context.device(), gather_sets_->layout(), "cell_gather.comp");
  context.run_once([&](VkCommandBuffer commands) { vkCmdFillBuffer(commands, cells_.buffer(), 0, VK_WHOLE_SIZE, 0); });
}

CellBuffer::~CellBuffer() = default;

std::uint64_t CellBuffer::record_upload(VkCommandBuffer commands, int slot, const granular::World& world,
                                        std::span<const std::uint32_t> bricks) {
  if (bricks.empty()) return 0;
  wait_for_readers(commands);
  std::uint64_t uploaded = 0;
  if (most_bricks(bricks.size())) {
    const granular::Box whole{{0, 0, 0}, size_};
    const VkDeviceSize bytes = VkDeviceSize(whole.volume());
    staging_.reserve(slot, bytes);
    world.read_region(whole, std::span<std::uint8_t>(static_cast<std::uint8_t*>(staging_.at(slot).mapped()), bytes));
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(commands, staging_.at(slot).buffer(), cells_.buffer(), 1, &region);
    uploaded = bytes;
  } else {
    const VkDeviceSize bytes = bricks.size() * kBrickCells;
    staging_.reserve(slot, bytes);
    brick_lists_.reserve(slot, bricks.size() * 4);
    scatter_sets_->write_buffer(slot, 1, brick_lists_.at(slot).buffer());
    scatter_sets_->write_buffer(slot, 2, staging_.at(slot).buffer());
    std::memcpy(brick_lists_.at(slot).mapped(), bricks.data(), bricks.size() * 4);
    auto* packed = static_cast<std::uint8_t*>(staging_.at(slot).mapped());
    std::vector<std::uint8_t> partial;
    for (std::size_t i = 0; i < bricks.size(); ++i) {
      const granular::Box box = granular::brick_box(size_, bricks[i]);
      std::uint8_t* out = packed + i * kBrickCells;
      if (VkDeviceSize(box.volume()) == kBrickCells) {
        world.read_region(box, std::span<std::uint8_t>(out, kBrickCells));
        continue;
      }
      partial.resize(std::size_t(box.volume()));
      world.read_region(box, partial);
      const granular::Int3 e = box.extent();
      for (int z = 0; z < e.z; ++z)
        for (int y = 0; y < e.y; ++y)
          std::memcpy(out + (z * granular::kBrickSize + y) * granular::kBrickSize, partial.data() + (std::size_t(z) * e.y + y) * e.x,
                      std::size_t(e.x));
    }
    dispatch_per_brick(commands, *scatter_, *scatter_sets_, slot, bricks.size());
    uploaded = bytes;
  }
  release_to_readers(commands);
  return uploaded;
}

bool CellBuffer::most_bricks(std::size_t bricks) const {
  const granular::Int3 counts = granular::brick_counts(size_);
  return bricks * 2 >= std::size_t(counts.x) * counts.y * counts.z;
}

void CellBuffer::dispatch_per_brick(VkCommandBuffer commands, const Pipeline& pass, const DescriptorSets& sets, int slot,
                                    std::size_t bricks) const {
  const granular::Int3 counts = granular::brick_counts(size_);
  ViewConstants constants;
  constants.grid = {size_.x, size_.y, size_.z, int(bricks)};
  constants.bricks = {counts.x, counts.y, counts.z, 0};
  pass.bind(commands, VK_PIPELINE_BIND_POINT_COMPUTE, sets.set(slot));
  vkCmdPushConstants(commands, pass.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(constants), &constants);
  vkCmdDispatch(commands, std::uint32_t(bricks), 1, 1);
}

std::uint64_t CellBuffer::record_copy_from(VkCommandBuffer commands, int slot, VkBuffer source,
                                          std::span<const std::uint32_t> bricks) {
  if (bricks.empty()) return 0;
  wait_for_readers(commands);
  std::uint64_t copied = 0;
  if (most_bricks(bricks.size())) {
    const VkBufferCopy region{0, 0, cells_.size()};
    vkCmdCopyBuffer(commands, source, cells_.buffer(), 1, &region);
    copied = cells_.size();
  } else {
    gather_lists_.reserve(slot, bricks.size() * 4);
    std::memcpy(gather_lists_.at(slot).mapped(), bricks.data(), bricks.size() * 4);
    gather_sets_->write_buffer(slot, 1, gather_lists_.at(slot).buffer());
    gather_sets_->write_buffer(slot, 2, source);
    dispatch_per_brick(commands, *gather_, *gather_sets_, slot, bricks.size());
    copied = bricks.size() * kBrickCells;
  }
  release_to_readers(commands);
  return copied;
}

}  // namespace viewer
