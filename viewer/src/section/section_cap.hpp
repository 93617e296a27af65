#pragma once
/// @file section_cap.hpp
/// The face a section plane cuts, for the raster renderers: one quad over the grid's cross-section
/// at the plane, each point showing the kept cell behind it in its colour
/// (shaders/section_cap.vert, section_cap.frag). Drawn only while a section is on; it reads the
/// cell buffer directly, so moving the plane rebuilds nothing.

#include <vulkan/vulkan.h>

#include "vulkan/pipeline_builder.hpp"
#include "renderers/renderer.hpp"

namespace viewer {

class VulkanContext;
class CellBuffer;
class MaterialPalette;

/// The section's cap of one raster renderer.
class SectionCap {
 public:
  /// Reads `cells` and `palette` (which must outlive it) and draws into passes compatible with
  /// `target_pass`. With `cut_faces_only`, covers only the cells whose face at the plane a cube
  /// build left out (its neighbour across the plane is not void): the instanced cubes draw the
  /// others; otherwise every kept cell at the plane (the marching cubes clip their surfaces there).
  SectionCap(const VulkanContext& context, const CellBuffer& cells, const MaterialPalette& palette, VkRenderPass target_pass,
             bool cut_faces_only);

  /// Records the opaque cells' cap (nothing without a section).
  void draw_opaque(VkCommandBuffer commands, const FrameView& view) const;
  /// Records the cap of the liquids and gases, then, under x-ray, of the static materials, blended
  /// (nothing without a section).
  void draw_translucent(VkCommandBuffer commands, const FrameView& view) const;

 private:
  void draw(VkCommandBuffer commands, const FrameView& view, const Pipeline& pipeline, DrawPass pass) const;

  bool cut_faces_only_;
  DescriptorSets sets_;
  Pipeline opaque_;
  Pipeline translucent_;
};

}  // namespace viewer
