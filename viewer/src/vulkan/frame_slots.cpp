#include "vulkan/frame_slots.hpp"

#include <cstdint>

#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {

FrameSlots::FrameSlots(const VulkanContext& context) : device_(context.device()), pool_(context.command_pool()) {
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = kFramesInFlight;
  vk_check(vkAllocateCommandBuffers(device_, &allocate, commands_.data()), "vkAllocateCommandBuffers");
  try {
    for (VkFence& fence : fences_) {
      VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
      info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
      vk_check(vkCreateFence(device_, &info, nullptr, &fence), "vkCreateFence");
    }
  } catch (...) {
    release();
    throw;
  }
}

FrameSlots::~FrameSlots() { release(); }

void FrameSlots::release() noexcept {
  for (VkFence& fence : fences_)
    if (fence) vkDestroyFence(device_, fence, nullptr);
  fences_.fill(VK_NULL_HANDLE);
  if (commands_[0]) vkFreeCommandBuffers(device_, pool_, kFramesInFlight, commands_.data());
  commands_.fill(VK_NULL_HANDLE);
}

void FrameSlots::wait(int slot) const {
  vk_check(vkWaitForFences(device_, 1, &fences_[slot], VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

void FrameSlots::wait_all() const {
  vk_check(vkWaitForFences(device_, kFramesInFlight, fences_.data(), VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

VkCommandBuffer FrameSlots::begin(int slot) const {
  vk_check(vkResetFences(device_, 1, &fences_[slot]), "vkResetFences");
  const VkCommandBuffer commands = commands_[slot];
  vk_check(vkResetCommandBuffer(commands, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk_check(vkBeginCommandBuffer(commands, &begin), "vkBeginCommandBuffer");
  return commands;
}

}  // namespace viewer
