#pragma once
/// @file shared_cells.hpp
/// CUDA interop, Vulkan side: the World's cells live in Vulkan memory exported as an opaque fd
/// (dedicated allocation where the driver asks for it), CUDA steps them in place, and two exported
/// timeline semaphores order the simulation's writes with the renderer's reads. Each frame a small
/// submission waits for the world's last write (cells_ready), copies the changed bricks into the
/// renderers' cell buffer on the device, and releases the cells (cells_released), so the next
/// simulation step overlaps the frame's build and draw. No host copy of the grid.

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>

#include "vulkan/frame_slots.hpp"
#include "vulkan/frames_in_flight.hpp"
#include "vulkan/vulkan_context.hpp"

namespace granular {
class World;
}

namespace viewer {

/// `options` set up for interop with `world` (external memory, the CUDA device's UUID) when the
/// world runs on the CUDA backend of a build that can share its cells; nothing otherwise.
std::optional<ContextOptions> interop_context(const granular::World& world, ContextOptions options);

/// The exported cell memory and timelines of one World (CUDA backend).
class SharedCells {
 public:
  /// Allocates exportable memory of world.shared_cell_bytes(), moves the world's cells into it
  /// (World::share_cells) and attaches two exported timelines (World::attach_timelines). The
  /// context must have been created with ContextOptions::external_memory on the CUDA device (same
  /// UUID). Throws VulkanError when the device cannot export, granular::BackendError from the world.
  /// Destroy the World (or stop using it) before this object.
  SharedCells(const VulkanContext& context, granular::World& world);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~SharedCells();
  SharedCells(const SharedCells&) = delete;
  SharedCells& operator=(const SharedCells&) = delete;

  /// The shared buffer (the cells as CUDA writes them).
  VkBuffer buffer() const { return buffer_; }
  /// True when the memory was allocated as a dedicated allocation.
  bool dedicated() const { return dedicated_; }

  /// Submits, on the context's queue, a command buffer that waits for every write of the world so
  /// far, acquires the shared buffer, lets `record_copy(commands, shared_buffer)` record the copy of
  /// what the frame needs (transfers or compute reading the buffer), releases it and signals the
  /// world that the cells are free again. `record_copy` records its own barriers for its destination.
  void submit_snapshot(int slot, const std::function<void(VkCommandBuffer, VkBuffer)>& record_copy);

 private:
  void release() noexcept;
  void create_memory(granular::World& world);
  VkSemaphore create_timeline(int& fd);

  const VulkanContext& context_;
  granular::World& world_;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  bool dedicated_ = false;
  VkSemaphore cells_ready_ = VK_NULL_HANDLE;
  VkSemaphore cells_released_ = VK_NULL_HANDLE;
  FrameSlots slots_;  ///< the snapshot copies' command buffers
};

}  // namespace viewer
