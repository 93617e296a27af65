#pragma once
/// @file cube_renderer.hpp
/// Instanced cubes: a compute pass lists, per brick, the non-void cells with a face showing (next
/// to void, or an opaque or liquid cell next to a translucent one) into the brick's fixed slot of
/// the instance buffer, opaque and translucent (liquid, gas) apart, and writes the brick's two
/// indirect draw commands; one multi-draw-indirect then draws the opaque instances, a second one
/// blends the translucent ones over them (depth-tested, not written), 18 vertices per instance.
/// Colours come from the world's material table (MaterialPalette). Only the bricks that changed
/// (and their neighbours) are rebuilt; the others keep their instances and commands. A section
/// plane collapses the instances it removes and its cap (SectionCap) shows the cut; x-ray draws the
/// static materials' instances again, blended (surface_draws.hpp).

#include <cstdint>
#include <memory>

#include "renderers/brick_surface_renderer.hpp"
#include "renderers/draw_compaction.hpp"
#include "vulkan/gpu_buffer.hpp"
#include "vulkan/pipeline_builder.hpp"

namespace viewer {

class VulkanContext;
class CellBuffer;
class MaterialPalette;

/// The instanced-cube renderer.
class CubeRenderer final : public BrickSurfaceRenderer {
 public:
  /// Reads `cells` and `palette` (which must outlive it) and draws into passes compatible with
  /// `target_pass`.
  CubeRenderer(const VulkanContext& context, const CellBuffer& cells, const MaterialPalette& palette,
               VkRenderPass target_pass);

  /// See Renderer (renderer.hpp): lists the changed bricks' instances and writes their commands.
  std::uint64_t prepare(VkCommandBuffer commands, const FrameView& view,
                        std::span<const std::uint32_t> changed_bricks) override;

 private:
  const DrawCompaction& compaction() const override { return compaction_; }

  GpuBuffer instances_;
  GpuBuffer draws_;  ///< brick_total_ opaque commands, then brick_total_ translucent ones
  Pipeline build_;
  DrawCompaction compaction_;  ///< draws_ compacted to the bricks that draw something
};

}  // namespace viewer
