#pragma once
/// @file frame_slots.hpp
/// The command buffers of the frames in flight, each with the fence its last submission signals:
/// what the offscreen renderer, the swapchain and the CUDA interop record a frame's work into.

#include <vulkan/vulkan.h>

#include <array>

#include "vulkan/frames_in_flight.hpp"

namespace viewer {

class VulkanContext;

/// kFramesInFlight primary command buffers from the context's pool, and a fence each (created
/// signalled, so the first wait returns at once).
class FrameSlots {
 public:
  /// Allocates the command buffers and creates the fences.
  explicit FrameSlots(const VulkanContext& context);
  /// Frees them (after the GPU is done with them).
  ~FrameSlots();
  FrameSlots(const FrameSlots&) = delete;
  FrameSlots& operator=(const FrameSlots&) = delete;

  /// Waits until the GPU has finished the last submission of `slot`.
  void wait(int slot) const;
  /// Waits until the GPU has finished the last submission of every slot.
  void wait_all() const;
  /// Starts recording `slot` (call after wait(slot)): resets its fence and command buffer and begins
  /// a one-time submission; returns the command buffer.
  VkCommandBuffer begin(int slot) const;
  /// The fence that the submission of `slot` must signal.
  VkFence fence(int slot) const { return fences_[slot]; }

 private:
  void release() noexcept;

  VkDevice device_;
  VkCommandPool pool_;
  std::array<VkCommandBuffer, kFramesInFlight> commands_{};
  std::array<VkFence, kFramesInFlight> fences_{};
};

}  // namespace viewer
