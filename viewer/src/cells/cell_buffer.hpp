#pragma once
/// @file cell_buffer.hpp
/// The GPU copy of the cell grid, byte for byte the World's layout (x fastest, then y, then z),
/// kept current by uploading only the bricks that changed through per-frame staging buffers.

#include <cstdint>
#include <memory>
#include <span>

#include "vulkan/gpu_buffer.hpp"
#include "granular/geometry.hpp"
#include "vulkan/host_buffer_slots.hpp"

namespace granular {
class World;
}

namespace viewer {

class VulkanContext;
class Pipeline;
class DescriptorSets;

/// A device-local storage buffer of one byte per cell, plus the upload machinery.
class CellBuffer {
 public:
  /// A buffer for a grid of `size` cells.
  CellBuffer(const VulkanContext& context, granular::Int3 size);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~CellBuffer();
  CellBuffer(const CellBuffer&) = delete;
  CellBuffer& operator=(const CellBuffer&) = delete;

  /// The storage buffer renderers read.
  VkBuffer buffer() const { return cells_.buffer(); }
  /// Grid extent.
  granular::Int3 size() const { return size_; }
  /// Buffer size in bytes (the cells rounded up to whole 4-byte words).
  VkDeviceSize bytes() const { return cells_.size(); }

  /// Copies the cells of `bricks` from `world` into slot `slot`'s staging buffer and records their
  /// transfer into the cell buffer (one copy of the whole grid when most bricks changed, else a
  /// scatter pass over packed bricks), followed by a barrier making the cells visible to shaders.
  /// Returns the bytes uploaded.
  std::uint64_t record_upload(VkCommandBuffer commands, int slot, const granular::World& world,
                              std::span<const std::uint32_t> bricks);
  /// Records a device-side copy of the cells of `bricks` from `source` (a grid of the same size and
  /// layout, e.g. the cells shared with CUDA, already readable by transfers and shaders): the
  /// whole buffer when most bricks changed, else a gather pass over the listed bricks; barriers
  /// order it after earlier readers and before later shader reads. Returns the bytes copied.
  std::uint64_t record_copy_from(VkCommandBuffer commands, int slot, VkBuffer source,
                                 std::span<const std::uint32_t> bricks);

 private:
  /// True when `bricks` changed bricks are at least half the grid's: one whole copy is cheaper.
  bool most_bricks(std::size_t bricks) const;
  /// Records `pass` over `bricks` listed bricks, one workgroup per brick, with the grid's constants.
  void dispatch_per_brick(VkCommandBuffer commands, const Pipeline& pass, const DescriptorSets& sets, int slot,
                          std::size_t bricks) const;

  const VulkanContext& context_;
  granular::Int3 size_;
  GpuBuffer cells_;
  HostBufferSlots staging_;
  HostBufferSlots brick_lists_;
  std::unique_ptr<DescriptorSets> scatter_sets_;
  std::unique_ptr<Pipeline> scatter_;
  HostBufferSlots gather_lists_;
  std::unique_ptr<DescriptorSets> gather_sets_;
  std::unique_ptr<Pipeline> gather_;
};

}  // namespace viewer
