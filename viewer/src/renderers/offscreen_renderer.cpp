#include "renderers/offscreen_renderer.hpp"

#include <cstdint>
#include <utility>

#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {

OffscreenRenderer::OffscreenRenderer(const VulkanContext& context, const granular::World& world, VkExtent2D extent,
                                     RendererKind kind, SharedCells* shared, const RenderDetail& detail)
    : context_(context), slots_(context) {
  target_ = std::make_unique<RenderTarget>(context, extent);
  renderer_ = std::make_unique<WorldRenderer>(context, world, target_->compatible_pass(), kind, shared, detail);
}

OffscreenRenderer::~OffscreenRenderer() {
  wait_idle();
}

void OffscreenRenderer::wait_idle() const {
  slots_.wait_all();
}

FrameWork OffscreenRenderer::render(const OrbitCamera& camera, const BrushView& brush) {
  slots_.wait(slot_);
  if (in_use_[slot_]) finished_.push_back(renderer_->timings(slot_));
  in_use_[slot_] = true;
  VkCommandBuffer commands = slots_.begin(slot_);
  const FrameWork work = renderer_->record(commands, slot_, *target_, 0, VK_IMAGE_LAYOUT_UNDEFINED, camera, brush);
  vk_check(vkEndCommandBuffer(commands), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  vk_check(vkQueueSubmit(context_.queue(), 1, &submit, slots_.fence(slot_)), "vkQueueSubmit");
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
  slots_.wait(last_slot_);
  return renderer_->timings(last_slot_);
}

std::vector<GpuTimings> OffscreenRenderer::take_finished_timings() { return std::exchange(finished_, {}); }

void OffscreenRenderer::set_kind(RendererKind kind) {
  wait_idle();
  renderer_->set_kind(kind);
}

}  // namespace viewer
