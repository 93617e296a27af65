#pragma once
/// @file host_buffer_slots.hpp
/// One mapped host-visible buffer per frame slot, grown on demand: staging for uploads and the
/// brick lists of build passes, written by the CPU while the GPU may still read another slot's.

#include <array>

#include "vulkan/frames_in_flight.hpp"
#include "vulkan/gpu_buffer.hpp"

namespace viewer {

class VulkanContext;

/// Per-slot host buffers of one usage.
class HostBufferSlots {
 public:
  /// Buffers usable as `usage`; none is allocated until reserve().
  HostBufferSlots(const VulkanContext& context, VkBufferUsageFlags usage) : context_(context), usage_(usage) {}
  /// Slot `slot`'s buffer with room for at least `bytes`; reallocated (contents lost) when smaller.
  /// Returns true when the VkBuffer changed (descriptors pointing at it must be rewritten).
  bool reserve(int slot, VkDeviceSize bytes);
  /// Slot `slot`'s buffer.
  const GpuBuffer& at(int slot) const { return buffers_[slot]; }

 private:
  const VulkanContext& context_;
  VkBufferUsageFlags usage_;
  std::array<GpuBuffer, kFramesInFlight> buffers_;
};

}  // namespace viewer
