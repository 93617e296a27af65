#include "vulkan/host_buffer_slots.hpp"

#include <algorithm>

namespace viewer {

bool HostBufferSlots::reserve(int slot, VkDeviceSize bytes) {
  if (buffers_[slot].buffer() && buffers_[slot].size() >= bytes) return false;
  const VkDeviceSize grown = std::max<VkDeviceSize>({bytes, buffers_[slot].size() * 3 / 2, 4096});
  buffers_[slot] = GpuBuffer(context_, grown, usage_, MemoryKind::HostVisible);
  return true;
}

}  // namespace viewer
