#pragma once
/// @file marching_cubes_renderer.hpp
/// Marching cubes: a compute pass meshes, per brick, the iso-surface of each look's density (opaque,
/// liquid, gas: every look a surface of its own, so the ground under water is meshed too) into the
/// brick's fixed slots of the vertex and index buffers (3072 triangles and as many vertices a brick,
/// fewer where the device's buffer limits require; a brick's excess triangles are dropped; the
/// triangles share their vertices) and writes the brick's two indexed indirect draw commands; one
/// multi-draw-indirect draws the opaque surfaces of every brick, a second one blends
/// the translucent ones over them (depth-tested, not written). Colours come from the world's
/// material table (MaterialPalette). Only the bricks that changed (and their neighbours) are
/// re-meshed. Where cells are small on the image a brick is meshed with a cube per 2x2x2 cells
/// (BrickDetail), and re-meshed when its level changes. A section plane clips the surfaces and its
/// cap (SectionCap) closes the cut; x-ray meshes the static materials apart and draws them blended
/// (surface_draws.hpp).

#include <cstdint>

#include "cells/brick_detail.hpp"
#include "renderers/brick_surface_renderer.hpp"
#include "renderers/draw_compaction.hpp"
#include "vulkan/gpu_buffer.hpp"
#include "vulkan/host_buffer_slots.hpp"
#include "vulkan/pipeline_builder.hpp"

namespace viewer {

class VulkanContext;
class CellBuffer;
class MaterialPalette;

/// The marching-cubes renderer.
class MarchingCubesRenderer final : public BrickSurfaceRenderer {
 public:
  /// Reads `cells` and `palette` (which must outlive it) and draws into passes compatible with
  /// `target_pass`, keeping `detail`.
  MarchingCubesRenderer(const VulkanContext& context, const CellBuffer& cells, const MaterialPalette& palette,
                        VkRenderPass target_pass, const RenderDetail& detail);

  /// See Renderer (renderer.hpp): classifies and meshes the changed bricks (and those whose level
  /// of detail changed).
  std::uint64_t prepare(VkCommandBuffer commands, const FrameView& view,
                        std::span<const std::uint32_t> changed_bricks) override;

 private:
  const DrawCompaction& compaction() const override { return compaction_; }

  /// Records the copy of detail_'s levels into levels_ through slot `slot`'s staging buffer.
  void upload_levels(VkCommandBuffer commands, int slot);

  std::uint32_t triangles_per_brick_;
  GpuBuffer vertices_;  ///< triangles_per_brick_ vertices a brick
  GpuBuffer indices_;   ///< triangles_per_brick_ x 3 indices a brick, into its vertices
  GpuBuffer draws_;     ///< brick_total_ opaque indexed commands, then brick_total_ translucent ones
  GpuBuffer mesh_list_;  ///< the build's indirect dispatch, then the bricks it meshes (mc_classify.comp)
  GpuBuffer cases_;
  BrickDetail detail_;
  HostBufferSlots level_staging_;  ///< detail_'s levels on their way to levels_
  GpuBuffer levels_;               ///< a byte per brick: the level it is meshed at (mc_build.comp)
  std::vector<std::uint32_t> level_rebuild_;  ///< bricks to re-mesh for a change of level
  Pipeline classify_;
  Pipeline build_;
  DrawCompaction compaction_;  ///< draws_ compacted to the bricks that draw something
};

}  // namespace viewer
