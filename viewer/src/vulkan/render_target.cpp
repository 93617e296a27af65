#include "vulkan/render_target.hpp"

#include <cstdint>
#include <array>
#include <cstring>
#include <utility>

#include "vulkan/barriers.hpp"
#include "vulkan/device_image.hpp"
#include "vulkan/gpu_buffer.hpp"
#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

VkRenderPass create_pass(VkDevice device, VkFormat color, VkFormat depth, ColorLoad load, VkImageLayout final_layout) {
  std::array<VkAttachmentDescription, 2> attachments{};
  attachments[0].format = color;
  attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
  attachments[0].loadOp = load == ColorLoad::Clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
  attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[0].initialLayout = load == ColorLoad::Clear ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  attachments[0].finalLayout = final_layout;
  attachments[1].format = depth;
  attachments[1].samples = VK_SAMPLE_COUNT_1_BIT;
  attachments[1].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[1].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachments[1].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[1].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &color_ref;
  subpass.pDepthStencilAttachment = &depth_ref;
  // Earlier work on the attachments (previous frame's reads, the blit, the transfer out) finishes
  // before this pass writes them; this pass's writes finish before later transfers read them.
  std::array<VkSubpassDependency, 2> dependencies{};
  dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[0].dstSubpass = 0;
  dependencies[0].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT |
                                 VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependencies[0].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                  VK_ACCESS_TRANSFER_WRITE_BIT;
  dependencies[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  dependencies[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT |
                                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
  dependencies[1].srcSubpass = 0;
  dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dependencies[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT;
  dependencies[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = std::uint32_t(attachments.size());
  info.pAttachments = attachments.data();
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = std::uint32_t(dependencies.size());
  info.pDependencies = dependencies.data();
  VkRenderPass pass = VK_NULL_HANDLE;
  vk_check(vkCreateRenderPass(device, &info, nullptr, &pass), "vkCreateRenderPass");
  return pass;
}

}  // namespace

RenderTarget::RenderTarget(const VulkanContext& context, VkExtent2D extent) : device_(context.device()), extent_(extent) {
  try {
    owned_color_ = create_device_image(context, extent, color_format_,
                                       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                           VK_IMAGE_USAGE_TRANSFER_DST_BIT);
    color_images_.push_back(owned_color_.image);
    create_common(context, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  } catch (...) {
    release();
    throw;
  }
}

RenderTarget::RenderTarget(const VulkanContext& context, VkExtent2D extent, VkFormat format,
                           const std::vector<VkImage>& images)
    : device_(context.device()), extent_(extent), color_format_(format), color_images_(images) {
  try {
    create_common(context, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
  } catch (...) {
    release();
    throw;
  }
}

void RenderTarget::create_common(const VulkanContext& context, VkImageLayout final_layout) {
  for (VkImage image : color_images_) color_views_.push_back(create_image_view(device_, image, color_format_, VK_IMAGE_ASPECT_COLOR_BIT));
  depth_ = create_device_image(context, extent_, depth_format_, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
  depth_.view = create_image_view(device_, depth_.image, depth_format_, VK_IMAGE_ASPECT_DEPTH_BIT);
  clear_pass_ = create_pass(device_, color_format_, depth_format_, ColorLoad::Clear, final_layout);
  load_pass_ = create_pass(device_, color_format_, depth_format_, ColorLoad::Load, final_layout);
  for (VkImageView view : color_views_) {
    const std::array<VkImageView, 2> attachments{view, depth_.view};
    VkFramebufferCreateInfo info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    info.renderPass = clear_pass_;
    info.attachmentCount = 2;
    info.pAttachments = attachments.data();
    info.width = extent_.width;
    info.height = extent_.height;
    info.layers = 1;
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    vk_check(vkCreateFramebuffer(device_, &info, nullptr, &framebuffer), "vkCreateFramebuffer");
    framebuffers_.push_back(framebuffer);
  }
}

RenderTarget::~RenderTarget() { release(); }

void RenderTarget::release() noexcept {
  for (VkFramebuffer framebuffer : framebuffers_) vkDestroyFramebuffer(device_, framebuffer, nullptr);
  framebuffers_.clear();
  if (clear_pass_) vkDestroyRenderPass(device_, clear_pass_, nullptr);
  if (load_pass_) vkDestroyRenderPass(device_, load_pass_, nullptr);
  clear_pass_ = load_pass_ = VK_NULL_HANDLE;
  destroy_device_image(device_, depth_);
  for (VkImageView view : color_views_) vkDestroyImageView(device_, view, nullptr);
  color_views_.clear();
  destroy_device_image(device_, owned_color_);
}

void RenderTarget::begin(VkCommandBuffer commands, std::uint32_t index, ColorLoad load) const {
  std::array<VkClearValue, 2> clears{};
  clears[0].color = {{0.62f, 0.72f, 0.84f, 1.0f}};
  clears[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  info.renderPass = load == ColorLoad::Clear ? clear_pass_ : load_pass_;
  info.framebuffer = framebuffers_[index];
  info.renderArea = {{0, 0}, extent_};
  info.clearValueCount = 2;
  info.pClearValues = clears.data();
  vkCmdBeginRenderPass(commands, &info, VK_SUBPASS_CONTENTS_INLINE);
  const VkViewport viewport{0, 0, float(extent_.width), float(extent_.height), 0, 1};
  const VkRect2D scissor{{0, 0}, extent_};
  vkCmdSetViewport(commands, 0, 1, &viewport);
  vkCmdSetScissor(commands, 0, 1, &scissor);
}

void RenderTarget::end(VkCommandBuffer commands) const { vkCmdEndRenderPass(commands); }

std::vector<std::uint8_t> RenderTarget::read_pixels(const VulkanContext& context, std::uint32_t index,
                                                    VkImageLayout layout) const {
  const VkDeviceSize bytes = VkDeviceSize(extent_.width) * extent_.height * 4;
  GpuBuffer readback(context, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryKind::HostVisible);
  const VkImage image = color_images_[index];
  context.run_once([&](VkCommandBuffer commands) {
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
      transition_color_image(commands, image, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent_.width, extent_.height, 1};
    vkCmdCopyImageToBuffer(commands, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer(), 1, &region);
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
      transition_color_image(commands, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout);
  });
  std::vector<std::uint8_t> pixels(bytes);
  std::memcpy(pixels.data(), readback.mapped(), bytes);
  if (color_format_ == VK_FORMAT_B8G8R8A8_UNORM || color_format_ == VK_FORMAT_B8G8R8A8_SRGB)
    for (std::size_t i = 0; i < pixels.size(); i += 4) std::swap(pixels[i], pixels[i + 2]);
  return pixels;
}

void transition_color_image(VkCommandBuffer commands, VkImage image, VkImageLayout from, VkImageLayout to) {
  VkImageMemoryBarrier2 barrier = scoped(VkImageMemoryBarrier2{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2},
                                         {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                                          VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                          VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT});
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.image = image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  record_barrier(commands, barrier);
}

}  // namespace viewer
