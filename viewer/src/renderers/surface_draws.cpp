#include "renderers/surface_draws.hpp"

#include "renderers/draw_compaction.hpp"
#include "vulkan/pipeline_builder.hpp"
#include "section/section_cap.hpp"

namespace viewer {
namespace {

/// Binds `pipeline`, pushes the view's constants for `pass` and draws compacted list `list` (0 the
/// opaque commands, 1 the translucent ones).
void draw_half(VkCommandBuffer commands, const FrameView& view, const SurfaceDraws& draws, const Pipeline& pipeline,
               DrawPass pass, int list) {
  ViewConstants constants = view.raster;
  constants.grid.w = for_draw(constants.grid.w, pass);
  pipeline.bind(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, draws.set);
  vkCmdPushConstants(commands, pipeline.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(constants), &constants);
  draws.compaction.draw(commands, list);
}

}  // namespace

void record_surface_draws(VkCommandBuffer commands, const FrameView& view, const SurfaceDraws& draws) {
  draw_half(commands, view, draws, draws.opaque, DrawPass::Opaque, 0);
  draws.cap.draw_opaque(commands, view);
  draw_half(commands, view, draws, draws.translucent, DrawPass::Translucent, 1);
  if (view.inside.xray) draw_half(commands, view, draws, draws.translucent, DrawPass::Xray, 0);
  draws.cap.draw_translucent(commands, view);
}

}  // namespace viewer
