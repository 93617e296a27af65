#include "section/section_cap.hpp"

#include "cells/cell_buffer.hpp"
#include "cells/material_palette.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

/// A cap pipeline's options: either side of the quad may face the eye.
GraphicsOptions both_sides(GraphicsOptions options) {
  options.cull = VK_CULL_MODE_NONE;
  return options;
}

}  // namespace

SectionCap::SectionCap(const VulkanContext& context, const CellBuffer& cells, const MaterialPalette& palette,
                       VkRenderPass target_pass, bool cut_faces_only)
    : cut_faces_only_(cut_faces_only),
      sets_(context.device(), storage_then_palette(1)),  // cells; the palette at 1
      opaque_(context.device(), sets_.layout(), target_pass, "section_cap.vert", "section_cap.frag", both_sides({})),
      translucent_(context.device(), sets_.layout(), target_pass, "section_cap.vert", "section_cap.frag",
                   both_sides(GraphicsOptions::translucent())) {
  sets_.write_buffer(0, cells.buffer());
  sets_.write_buffer(1, palette.buffer());
}

void SectionCap::draw_opaque(VkCommandBuffer commands, const FrameView& view) const {
  draw(commands, view, opaque_, DrawPass::Opaque);
}

void SectionCap::draw_translucent(VkCommandBuffer commands, const FrameView& view) const {
  draw(commands, view, translucent_, DrawPass::Translucent);
  if (view.inside.xray) draw(commands, view, translucent_, DrawPass::Xray);
}

void SectionCap::draw(VkCommandBuffer commands, const FrameView& view, const Pipeline& pipeline, DrawPass pass) const {
  if (!view.inside.section.on()) return;
  ViewConstants constants = view.raster;
  constants.grid.w = for_draw(constants.grid.w, pass, cut_faces_only_);
  pipeline.bind(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, sets_.set(view.slot));
  vkCmdPushConstants(commands, pipeline.layout(), VK_SHADER_STAGE_ALL, 0, sizeof(constants), &constants);
  vkCmdDraw(commands, 6, 1, 0, 0);
}

}  // namespace viewer
