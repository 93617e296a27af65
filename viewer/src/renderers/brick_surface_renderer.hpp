#pragma once
/// @file brick_surface_renderer.hpp
/// What the renderers that mesh the grid brick by brick (instanced cubes, marching cubes) share:
/// the brick grid, the descriptor sets their passes bind, the list of bricks to rebuild, the opaque
/// and translucent pipelines of their surface shaders, the section cap, and the draw sequence of
/// surface_draws.hpp over the compacted indirect commands their build writes.

#include <cstdint>
#include <vector>

#include "cells/brick_rebuild_list.hpp"
#include "granular/geometry.hpp"
#include "renderers/draw_compaction.hpp"
#include "renderers/renderer.hpp"
#include "section/section_cap.hpp"
#include "vulkan/pipeline_builder.hpp"

namespace viewer {

class VulkanContext;
class CellBuffer;
class MaterialPalette;

/// The surface shaders of a brick renderer and how its section cap covers the plane.
struct SurfaceShaders {
  const char* vertex;     ///< vertex shader (SPIR-V name without .spv) of both surface pipelines
  const char* fragment;   ///< fragment shader of both
  bool cap_cut_faces_only;  ///< SectionCap's cut_faces_only: the cubes draw the cells the cap does not
};

/// A renderer whose build meshes changed bricks into per-brick slots and writes two indirect
/// commands a brick (opaque, translucent), compacted by a DrawCompaction; derived classes own the
/// build, the buffers and the compaction, and record prepare().
class BrickSurfaceRenderer : public Renderer {
 public:
  /// See Renderer (renderer.hpp).
  RendererKind kind() const final { return kind_; }
  /// See Renderer (renderer.hpp).
  void invalidate() final { rebuild_.invalidate(); }
  /// See Renderer (renderer.hpp): the sequence of surface_draws.hpp.
  void draw(VkCommandBuffer commands, const FrameView& view) final;

 protected:
  /// A renderer of `kind` over `cells` (bricks of its size) with descriptor bindings of `bindings`
  /// (the cells at 0, the brick list at 1), drawing `shaders` into passes compatible with `target_pass`.
  BrickSurfaceRenderer(RendererKind kind, const VulkanContext& context, const CellBuffer& cells,
                       const MaterialPalette& palette, VkRenderPass target_pass,
                       const std::vector<VkDescriptorType>& bindings, const SurfaceShaders& shaders);

  /// The compacted indirect commands that draw() draws.
  virtual const DrawCompaction& compaction() const = 0;

  const granular::Int3 brick_counts_;  ///< bricks along x, y, z
  const std::uint32_t brick_total_;    ///< bricks in all
  DescriptorSets sets_;                ///< what every pass binds (per frame slot)
  BrickRebuildList rebuild_;           ///< after sets_: binds its lists there (binding 1)

 private:
  RendererKind kind_;
  Pipeline draw_pipeline_;
  Pipeline translucent_pipeline_;
  SectionCap cap_;
};

}  // namespace viewer
