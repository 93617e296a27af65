#pragma once
/// @file swapchain.hpp
/// The window's swapchain with a RenderTarget over its images, and the per-frame synchronisation of
/// frames in flight: a fence and an image-available semaphore per slot, a render-finished
/// semaphore per image. Recreated on resize.

#include <cstdint>
#include <vulkan/vulkan.h>

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "vulkan/frame_slots.hpp"
#include "vulkan/frames_in_flight.hpp"
#include "vulkan/render_target.hpp"

namespace viewer {

class VulkanContext;

/// An acquired image, ready to be recorded into.
struct AcquiredFrame {
  int slot = 0;                   ///< frame-in-flight slot
  std::uint32_t image_index = 0;  ///< swapchain image
  VkCommandBuffer commands = VK_NULL_HANDLE;  ///< the slot's command buffer, begun
};

/// Swapchain + render target + frame sync.
class Swapchain {
 public:
  /// Creates the swapchain for the context's surface at `extent`.
  Swapchain(const VulkanContext& context, VkExtent2D extent);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  /// Waits for the slot's previous frame, acquires an image and begins the slot's command buffer;
  /// nothing when the swapchain is out of date (call recreate() and try the next frame).
  std::optional<AcquiredFrame> begin_frame();
  /// Ends, submits and presents the frame; returns false when the swapchain must be recreated.
  bool end_frame(const AcquiredFrame& frame);
  /// Recreates everything at `extent` (waits for the device).
  void recreate(VkExtent2D extent);

  /// The render target over the swapchain images.
  const RenderTarget& target() const { return *target_; }
  /// Number of images.
  std::uint32_t image_count() const { return std::uint32_t(images_.size()); }
  /// The image presented last (for a screenshot after the device went idle).
  std::uint32_t last_presented() const { return last_presented_; }
  /// The minimum image count asked for.
  std::uint32_t min_image_count() const { return min_image_count_; }

 private:
  void create(VkExtent2D extent);
  void destroy_swapchain();

  const VulkanContext& context_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  std::vector<VkImage> images_;
  std::uint32_t min_image_count_ = 2;
  std::unique_ptr<RenderTarget> target_;
  FrameSlots slots_;
  std::array<VkSemaphore, kFramesInFlight> image_available_{};
  std::vector<VkSemaphore> render_finished_;
  int slot_ = 0;
  std::uint32_t last_presented_ = 0;
};

}  // namespace viewer
