#include "cells/brick_rebuild_list.hpp"

#include <cstring>
#include <vector>

#include "cells/brick_set.hpp"
#include "vulkan/pipeline_builder.hpp"

namespace viewer {

namespace {
constexpr VkDeviceSize kInitialListBytes = 4096;
}  // namespace

BrickRebuildList::BrickRebuildList(const VulkanContext& context, granular::Int3 brick_counts, DescriptorSets& sets,
                                   int binding)
    : lists_(context, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT), sets_(sets), binding_(binding), brick_counts_(brick_counts) {
  for (int slot = 0; slot < kFramesInFlight; ++slot) {
    lists_.reserve(slot, kInitialListBytes);
    sets_.write_buffer(slot, binding_, lists_.at(slot).buffer());
  }
}

std::uint32_t BrickRebuildList::upload(int slot, std::span<const std::uint32_t> changed) {
  std::vector<std::uint32_t> every;
  if (rebuild_all_) {
    every = all_bricks(brick_counts_);
    changed = every;
    rebuild_all_ = false;
  }
  if (changed.empty()) return 0;
  if (lists_.reserve(slot, changed.size_bytes())) sets_.write_buffer(slot, binding_, lists_.at(slot).buffer());
  std::memcpy(lists_.at(slot).mapped(), changed.data(), changed.size_bytes());
  return std::uint32_t(changed.size());
}

}  // namespace viewer
