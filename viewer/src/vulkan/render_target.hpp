#pragma once
/// @file render_target.hpp
/// What a frame is drawn into: colour images (an offscreen image, or the swapchain's), one depth
/// image, the two compatible render passes (clear, or load after a compute renderer's blit) and a
/// framebuffer per colour image.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "vulkan/device_image.hpp"

namespace viewer {

class VulkanContext;

/// How a render pass treats the colour attachment it starts with.
enum class ColorLoad {
  Clear,  ///< cleared to the background colour (raster renderers)
  Load,   ///< kept; arrives in TRANSFER_DST_OPTIMAL (written by a blit, e.g. the ray-march renderer)
};

/// Colour + depth attachments and the render passes over them.
class RenderTarget {
 public:
  /// An offscreen target of `extent` with its own RGBA8 colour image, left in
  /// TRANSFER_SRC_OPTIMAL after a frame so that read_pixels() can copy it.
  RenderTarget(const VulkanContext& context, VkExtent2D extent);
  /// A target over the swapchain's `images` of `format`, left in PRESENT_SRC_KHR after a frame.
  RenderTarget(const VulkanContext& context, VkExtent2D extent, VkFormat format, const std::vector<VkImage>& images);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  /// Size in pixels.
  VkExtent2D extent() const { return extent_; }
  /// Colour format.
  VkFormat color_format() const { return color_format_; }
  /// Number of colour images (1 offscreen).
  std::uint32_t image_count() const { return std::uint32_t(color_images_.size()); }
  /// Colour image `index`.
  VkImage color_image(std::uint32_t index) const { return color_images_[index]; }
  /// A render pass compatible with every pass of this target (for pipeline creation).
  VkRenderPass compatible_pass() const { return clear_pass_; }
  /// Begins the render pass on image `index` with a full viewport and scissor set.
  void begin(VkCommandBuffer commands, std::uint32_t index, ColorLoad load) const;
  /// Ends the render pass.
  void end(VkCommandBuffer commands) const;
  /// Copies colour image `index` (in `layout`, to which it is returned) into RGBA8 bytes, rows top to
  /// bottom (BGRA formats are swizzled). The image needs TRANSFER_SRC usage. Waits for the GPU.
  std::vector<std::uint8_t> read_pixels(const VulkanContext& context, std::uint32_t index = 0,
                                        VkImageLayout layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL) const;

 private:
  void release() noexcept;
  void create_common(const VulkanContext& context, VkImageLayout final_layout);

  VkDevice device_ = VK_NULL_HANDLE;
  VkExtent2D extent_{};
  VkFormat color_format_ = VK_FORMAT_R8G8B8A8_UNORM;
  VkFormat depth_format_ = VK_FORMAT_D32_SFLOAT;
  std::vector<VkImage> color_images_;
  DeviceImage owned_color_;  ///< the offscreen target's colour image (its view is in color_views_)
  std::vector<VkImageView> color_views_;
  DeviceImage depth_;
  VkRenderPass clear_pass_ = VK_NULL_HANDLE;
  VkRenderPass load_pass_ = VK_NULL_HANDLE;
  std::vector<VkFramebuffer> framebuffers_;
};

/// Records a layout transition of colour image `image` (synchronization2, all commands to all commands).
void transition_color_image(VkCommandBuffer commands, VkImage image, VkImageLayout from, VkImageLayout to);

}  // namespace viewer
