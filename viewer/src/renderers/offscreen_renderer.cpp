#include "renderers/offscreen_renderer.hpp"

#include <cstdint>
#include <utility>

#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {

OffscreenRenderer::OffscreenRenderer(const VulkanContext& context, const granular::World& world, VkExtent2D extent,
                                     RendererKind kind, SharedCells* shared, const RenderDetail& detail)
    : context_(context) {
  target_ = std::make_unique<RenderTarget>(context, extent);
  renderer_ = std::make_unique<WorldRenderer>(context, world, target_->compatible_pass(), kind, shared, detail);
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = context.command_pool();
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = kFramesInFlight;
  vk_check(vkAllocateCommandBuffers(context.device(), &allocate, commands_.data()), "vkAllocateCommandBuffers");
  for (VkFence& fence : fences_) {
    VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    vk_check(vkCreateFence(context.device(), &info, nullptr, &fence), "vkCreateFence");
  }
}

OffscreenRenderer::~OffscreenRenderer() {
  wait_idle();
  for (VkFence fence : fences_)
    if (fence) vkDestroyFence(context_.device(), fence, nullptr);
  vkFreeCommandBuffers(context_.device(), context_.command_pool(), kFramesInFlight, commands_.data());
}

void OffscreenRenderer::wait_idle() const {
  vk_check(vkWaitForFences(context_.device(), kFramesInFlight, fences_.data(), VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

FrameWork OffscreenRenderer::render(const OrbitCamera& camera, const BrushView& brush) {
  const VkDevice device = context_.device();
  vk_check(vkWaitForFences(device, 1, &fences_[slot_], VK_TRUE, UINT64_MAX), "vkWaitForFences");
  if (in_use_[slot_]) finished_.push_back(renderer_->timings(slot_));
  in_use_[slot_] = true;
  vk_check(vkResetFences(device, 1, &fences_[slot_]), "vkResetFences");
  VkCommandBuffer commands = commands_[slot_];
  vk_check(vkResetCommandBuffer(commands, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk_check(vkBeginCommandBuffer(commands, &begin), "vkBeginCommandBuffer");
  const FrameWork work = renderer_->record(commands, slot_, *target_, 0, VK_IMAGE_LAYOUT_UNDEFINED, camera, brush);
  vk_check(vkEndCommandBuffer(commands), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  vk_check(vkQueueSubmit(context_.queue(), 1, &submit, fences_[slot_]), "vkQueueSubmit");
  last_slot_ = slot_;
  slot_ = (slot_ + 1) % kFramesInFlight;
  return work;
}

std::vector<std::uint8_t> OffscreenRenderer::pixels() {
  wait_idle();
  return target_->read_pixels(context_);
}

GpuTimings OffscreenRenderer::last_timings() {
  if (last_slot_ < 0) return {};
  vk_check(vkWaitForFences(context_.device(), 1, &fences_[last_slot_], VK_TRUE, UINT64_MAX), "vkWaitForFences");
  return renderer_->timings(last_slot_);
}

std::vector<GpuTimings> OffscreenRenderer::take_finished_timings() { return std::exchange(finished_, {}); }

void OffscreenRenderer::set_kind(RendererKind kind) {
  wait_idle();
  renderer_->set_kind(kind);
}

}  // namespace viewer
