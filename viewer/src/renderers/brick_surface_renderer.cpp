#include "renderers/brick_surface_renderer.hpp"

#include "cells/cell_buffer.hpp"
#include "granular/bricks.hpp"
#include "renderers/surface_draws.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {

BrickSurfaceRenderer::BrickSurfaceRenderer(RendererKind kind, const VulkanContext& context, const CellBuffer& cells,
                                           const MaterialPalette& palette, VkRenderPass target_pass,
                                           const std::vector<VkDescriptorType>& bindings, const SurfaceShaders& shaders)
    : brick_counts_(granular::brick_counts(cells.size())),
      brick_total_(std::uint32_t(brick_counts_.x) * brick_counts_.y * brick_counts_.z),
      sets_(context.device(), bindings),
      rebuild_(context, brick_counts_, sets_, 1),
      kind_(kind),
      draw_pipeline_(context.device(), sets_.layout(), target_pass, shaders.vertex, shaders.fragment),
      translucent_pipeline_(context.device(), sets_.layout(), target_pass, shaders.vertex, shaders.fragment,
                            GraphicsOptions::translucent()),
      cap_(context, cells, palette, target_pass, shaders.cap_cut_faces_only) {
  sets_.write_buffer(0, cells.buffer());
}

void BrickSurfaceRenderer::draw(VkCommandBuffer commands, const FrameView& view) {
  record_surface_draws(commands, view,
                       {draw_pipeline_, translucent_pipeline_, sets_.set(view.slot), compaction(), cap_});
}

}  // namespace viewer
