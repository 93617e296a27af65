#pragma once
/// @file gpu_buffer.hpp
/// A VkBuffer with its own memory: device-local, or host-visible and persistently mapped.

#include <vulkan/vulkan.h>

#include <cstdint>

namespace viewer {

class VulkanContext;

/// Where a GpuBuffer's memory lives.
enum class MemoryKind {
  DeviceLocal,  ///< fast GPU memory, not mapped
  HostVisible,  ///< host-visible, coherent, mapped for the buffer's lifetime (staging, readback)
};

/// A buffer and its dedicated memory block. Movable, not copyable.
class GpuBuffer {
 public:
  /// An empty handle.
  GpuBuffer() = default;
  /// Allocates `size` bytes (> 0) usable as `usage`.
  GpuBuffer(const VulkanContext& context, VkDeviceSize size, VkBufferUsageFlags usage, MemoryKind kind);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~GpuBuffer();
  /// Takes over `other`'s buffer, leaving it empty.
  GpuBuffer(GpuBuffer&& other) noexcept;
  /// Releases this buffer and takes over `other`'s.
  GpuBuffer& operator=(GpuBuffer&& other) noexcept;
  GpuBuffer(const GpuBuffer&) = delete;
  GpuBuffer& operator=(const GpuBuffer&) = delete;

  /// The buffer.
  VkBuffer buffer() const { return buffer_; }
  /// Its size in bytes.
  VkDeviceSize size() const { return size_; }
  /// The mapped bytes (HostVisible only, else nullptr).
  void* mapped() const { return mapped_; }

 private:
  void release() noexcept;

  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

}  // namespace viewer
