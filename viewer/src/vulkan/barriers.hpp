#pragma once
/// @file barriers.hpp
/// Pipeline barriers (synchronization2): the scope of a barrier, the common kinds, and recording one.

#include <vulkan/vulkan.h>

namespace viewer {

/// What a barrier orders: the stages and accesses before it and those after it.
struct BarrierScope {
  VkPipelineStageFlags2 src_stage;  ///< the stages that must finish first
  VkAccessFlags2 src_access;        ///< their writes made available
  VkPipelineStageFlags2 dst_stage;  ///< the stages that wait
  VkAccessFlags2 dst_access;        ///< their accesses the writes are made visible to
};

/// `barrier` (a VkMemoryBarrier2, VkBufferMemoryBarrier2 or VkImageMemoryBarrier2) with `scope`'s
/// stages and accesses, and for buffer and image barriers no queue family transfer.
template <class Barrier>
Barrier scoped(Barrier barrier, const BarrierScope& scope) {
  barrier.srcStageMask = scope.src_stage;
  barrier.srcAccessMask = scope.src_access;
  barrier.dstStageMask = scope.dst_stage;
  barrier.dstAccessMask = scope.dst_access;
  if constexpr (requires { barrier.srcQueueFamilyIndex; }) {
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  }
  return barrier;
}

/// A buffer memory barrier over the whole of `buffer`.
VkBufferMemoryBarrier2 whole_buffer_barrier(VkBuffer buffer, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                                            VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);
/// Records a global memory barrier from (src_stage, src_access) to (dst_stage, dst_access).
void memory_barrier(VkCommandBuffer commands, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

/// Records `barrier` alone into `commands`.
void record_barrier(VkCommandBuffer commands, const VkMemoryBarrier2& barrier);
/// Records `barrier` alone into `commands`.
void record_barrier(VkCommandBuffer commands, const VkBufferMemoryBarrier2& barrier);
/// Records `barrier` alone into `commands`.
void record_barrier(VkCommandBuffer commands, const VkImageMemoryBarrier2& barrier);

}  // namespace viewer
