#include "renderers/world_renderer.hpp"

#include <cstdint>
#include <vector>

#include "cells/brick_set.hpp"
#include "granular/bricks.hpp"
#include "granular/world.hpp"
#include "vulkan/render_target.hpp"
#include "renderers/renderer_factory.hpp"
#include "cells/shared_cells.hpp"
#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

constexpr std::uint32_t kQueriesPerFrame = 4;

}  // namespace

WorldRenderer::WorldRenderer(const VulkanContext& context, const granular::World& world, VkRenderPass target_pass,
                             RendererKind kind, SharedCells* shared, const RenderDetail& detail)
    : context_(context),
      world_(world),
      target_pass_(target_pass),
      shared_(shared),
      detail_(detail),
      palette_(context, world.rules().materials) {
  cells_ = std::make_unique<CellBuffer>(context, world.size());
  set_kind(kind);
  if (context.has_timestamps()) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = kQueriesPerFrame * kFramesInFlight;
    vk_check(vkCreateQueryPool(context.device(), &info, nullptr, &queries_), "vkCreateQueryPool");
  }
}

WorldRenderer::~WorldRenderer() {
  if (queries_) vkDestroyQueryPool(context_.device(), queries_, nullptr);
}

Renderer& WorldRenderer::renderer_of(RendererKind kind) {
  auto& renderer = renderers_[std::size_t(kind)];
  if (!renderer) renderer = make_renderer(kind, context_, *cells_, palette_, target_pass_, detail_);
  return *renderer;
}

void WorldRenderer::set_see_inside(const SeeInside& inside) {
  if (inside.xray != inside_.xray) active_->invalidate();
  inside_ = inside;
}

void WorldRenderer::release_inactive() {
  vkDeviceWaitIdle(context_.device());
  for (auto& renderer : renderers_)
    if (renderer.get() != active_) renderer.reset();
}

void WorldRenderer::set_kind(RendererKind kind) {
  Renderer& next = renderer_of(kind);
  if (&next != active_) next.invalidate();
  active_ = &next;
}

FrameWork WorldRenderer::record(VkCommandBuffer commands, int slot, const RenderTarget& target, std::uint32_t image_index,
                                VkImageLayout image_layout_before, const OrbitCamera& camera, const BrushView& brush,
                                const std::function<void(VkCommandBuffer)>& overlay) {
  const std::uint32_t first_query = std::uint32_t(slot) * kQueriesPerFrame;
  if (queries_) {
    vkCmdResetQueryPool(commands, queries_, first_query, kQueriesPerFrame);
    vkCmdWriteTimestamp2(commands, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_, first_query);
  }
  const granular::Int3 counts = world_.brick_counts();
  std::vector<std::uint32_t> changed =
      uploaded_once_ ? world_.bricks_changed_since(uploaded_version_) : all_bricks(counts);
  uploaded_once_ = true;
  uploaded_version_ = world_.change_version();
  FrameWork work;
  work.bricks_uploaded = changed.size();
  if (shared_) {
    shared_->submit_snapshot(slot, [&](VkCommandBuffer copy_commands, VkBuffer shared_cells) {
      work.bytes_uploaded = cells_->record_copy_from(copy_commands, slot, shared_cells, changed);
    });
  } else {
    work.bytes_uploaded = cells_->record_upload(commands, slot, world_, changed);
  }
  if (queries_) vkCmdWriteTimestamp2(commands, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_, first_query + 1);

  const VkExtent2D extent = target.extent();
  const float aspect = float(extent.width) / float(extent.height);
  const glm::mat4 view_projection = camera.projection(aspect) * camera.view();
  FrameView view;
  view.slot = slot;
  view.extent = extent;
  view.target_image = target.color_image(image_index);
  view.target_layout_before = image_layout_before;
  const granular::Int3 size = world_.size();
  view.raster.matrix = view_projection;
  view.raster.eye = glm::vec4(camera.eye(), brush.visible ? brush.radius : 0.0f);
  view.inside = inside_;
  view.raster.grid = {size.x, size.y, size.z, see_inside_word(inside_, size, camera.eye())};
  view.raster.bricks = {counts.x, counts.y, counts.z, int(extent.width)};
  view.raster.brush = glm::vec4(brush.center, float(extent.height));
  view.inverse = view.raster;
  view.inverse.matrix = glm::inverse(view_projection);
  const std::vector<std::uint32_t> rebuild = with_neighbours(changed, counts);
  work.bricks_rebuilt = active_->prepare(commands, view, rebuild);
  if (queries_) vkCmdWriteTimestamp2(commands, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_, first_query + 2);

  target.begin(commands, image_index, active_->color_load());
  active_->draw(commands, view);
  if (overlay) overlay(commands);
  target.end(commands);
  if (queries_) {
    vkCmdWriteTimestamp2(commands, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, queries_, first_query + 3);
    queries_written_[slot] = true;
  }
  return work;
}

GpuTimings WorldRenderer::timings(int slot) const {
  GpuTimings timings;
  if (!queries_ || !queries_written_[slot]) return timings;
  std::array<std::uint64_t, kQueriesPerFrame> stamps{};
  if (vkGetQueryPoolResults(context_.device(), queries_, std::uint32_t(slot) * kQueriesPerFrame, kQueriesPerFrame,
                            sizeof(stamps), stamps.data(), sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
    return timings;
  const double to_ms = context_.timestamp_period_ns() * 1e-6;
  timings.upload_ms = double(stamps[1] - stamps[0]) * to_ms;
  timings.build_ms = double(stamps[2] - stamps[1]) * to_ms;
  timings.draw_ms = double(stamps[3] - stamps[2]) * to_ms;
  return timings;
}

}  // namespace viewer
