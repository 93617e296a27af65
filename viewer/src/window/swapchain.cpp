#include "window/swapchain.hpp"

#include <cstdint>
#include <algorithm>

#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

VkSemaphore make_semaphore(VkDevice device) {
  VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VkSemaphore semaphore = VK_NULL_HANDLE;
  vk_check(vkCreateSemaphore(device, &info, nullptr, &semaphore), "vkCreateSemaphore");
  return semaphore;
}

}  // namespace

Swapchain::Swapchain(const VulkanContext& context, VkExtent2D extent) : context_(context), slots_(context) {
  for (VkSemaphore& semaphore : image_available_) semaphore = make_semaphore(context.device());
  create(extent);
}

Swapchain::~Swapchain() {
  const VkDevice device = context_.device();
  vkDeviceWaitIdle(device);
  destroy_swapchain();
  for (VkSemaphore semaphore : image_available_) vkDestroySemaphore(device, semaphore, nullptr);
}

void Swapchain::destroy_swapchain() {
  target_.reset();
  for (VkSemaphore semaphore : render_finished_) vkDestroySemaphore(context_.device(), semaphore, nullptr);
  render_finished_.clear();
  if (swapchain_) vkDestroySwapchainKHR(context_.device(), swapchain_, nullptr);
  swapchain_ = VK_NULL_HANDLE;
}

void Swapchain::create(VkExtent2D extent) {
  const VkPhysicalDevice physical = context_.physical_device();
  const VkSurfaceKHR surface = context_.surface();
  VkSurfaceCapabilitiesKHR capabilities;
  vk_check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface, &capabilities), "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  std::uint32_t format_count = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &format_count, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(format_count);
  vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &format_count, formats.data());
  if (formats.empty()) throw VulkanError("the window surface offers no formats");
  // UNORM, like the offscreen image, so windowed and headless frames look the same.
  VkSurfaceFormatKHR format = formats[0];
  for (const auto& candidate : formats)
    if ((candidate.format == VK_FORMAT_B8G8R8A8_UNORM || candidate.format == VK_FORMAT_R8G8B8A8_UNORM) &&
        candidate.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
      format = candidate;
  if (capabilities.currentExtent.width != UINT32_MAX) extent = capabilities.currentExtent;
  extent.width = std::clamp(extent.width, capabilities.minImageExtent.width, capabilities.maxImageExtent.width);
  extent.height = std::clamp(extent.height, capabilities.minImageExtent.height, capabilities.maxImageExtent.height);
  min_image_count_ = std::max(capabilities.minImageCount + 1, 2u);
  if (capabilities.maxImageCount) min_image_count_ = std::min(min_image_count_, capabilities.maxImageCount);

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface;
  info.minImageCount = min_image_count_;
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  // Transfer destination: the ray march blits into the image; source: --screenshot reads it back.
  info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                    (capabilities.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = capabilities.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
  info.clipped = VK_TRUE;
  vk_check(vkCreateSwapchainKHR(context_.device(), &info, nullptr, &swapchain_), "vkCreateSwapchainKHR");
  std::uint32_t image_count = 0;
  vkGetSwapchainImagesKHR(context_.device(), swapchain_, &image_count, nullptr);
  images_.resize(image_count);
  vkGetSwapchainImagesKHR(context_.device(), swapchain_, &image_count, images_.data());
  target_ = std::make_unique<RenderTarget>(context_, extent, format.format, images_);
  for (std::uint32_t i = 0; i < image_count; ++i) render_finished_.push_back(make_semaphore(context_.device()));
}

void Swapchain::recreate(VkExtent2D extent) {
  vkDeviceWaitIdle(context_.device());
  destroy_swapchain();
  create(extent);
}

std::optional<AcquiredFrame> Swapchain::begin_frame() {
  const VkDevice device = context_.device();
  slots_.wait(slot_);
  AcquiredFrame frame;
  frame.slot = slot_;
  const VkResult acquired =
      vkAcquireNextImageKHR(device, swapchain_, UINT64_MAX, image_available_[slot_], VK_NULL_HANDLE, &frame.image_index);
  if (acquired == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;
  vk_check(acquired, "vkAcquireNextImageKHR");
  frame.commands = slots_.begin(slot_);
  return frame;
}

bool Swapchain::end_frame(const AcquiredFrame& frame) {
  vk_check(vkEndCommandBuffer(frame.commands), "vkEndCommandBuffer");
  // The whole frame waits for the image: the ray-march renderer writes it with a blit.
  const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &image_available_[frame.slot];
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &frame.commands;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &render_finished_[frame.image_index];
  vk_check(vkQueueSubmit(context_.queue(), 1, &submit, slots_.fence(frame.slot)), "vkQueueSubmit");
  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &render_finished_[frame.image_index];
  present.swapchainCount = 1;
  present.pSwapchains = &swapchain_;
  present.pImageIndices = &frame.image_index;
  const VkResult presented = vkQueuePresentKHR(context_.queue(), &present);
  last_presented_ = frame.image_index;
  slot_ = (slot_ + 1) % kFramesInFlight;
  if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) return false;
  vk_check(presented, "vkQueuePresentKHR");
  return true;
}

}  // namespace viewer
