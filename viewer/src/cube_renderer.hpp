#pragma once
/// @file cube_renderer.hpp
/// Instanced cubes: a compute pass lists, per brick, the non-void cells with a void face neighbour
/// into the brick's fixed slot of the instance buffer and writes the brick's indirect draw command;
/// one multi-draw-indirect then draws 36 vertices per instance. Only the bricks that changed (and
/// their neighbours) are rebuilt; the others keep their instances and commands.

#include <cstdint>
#include <memory>

#include "gpu_buffer.hpp"
#include "granular/geometry.hpp"
#include "brick_rebuild_list.hpp"
#include "pipeline_builder.hpp"
#include "renderer.hpp"

namespace viewer {

class VulkanContext;
class CellBuffer;

/// The instanced-cube renderer.
class CubeRenderer final : public Renderer {
 public:
  /// Reads `cells` (which must outlive it) and draws into passes compatible with `target_pass`.
  CubeRenderer(const VulkanContext& context, const CellBuffer& cells, VkRenderPass target_pass);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~CubeRenderer() override;

  /// See Renderer (renderer.hpp).
  RendererKind kind() const override { return RendererKind::Cubes; }
  /// See Renderer (renderer.hpp).
  void invalidate() override { rebuild_.invalidate(); }
  /// See Renderer (renderer.hpp).
  std::uint64_t prepare(VkCommandBuffer commands, const FrameView& view,
                        std::span<const std::uint32_t> changed_bricks) override;
  /// See Renderer (renderer.hpp).
  void draw(VkCommandBuffer commands, const FrameView& view) override;

 private:
  const VulkanContext& context_;
  const CellBuffer& cells_;
  granular::Int3 brick_counts_;
  std::uint32_t brick_total_;
  GpuBuffer instances_;
  GpuBuffer draws_;
  DescriptorSets sets_;
  BrickRebuildList rebuild_;  ///< after sets_: binds its lists there
  Pipeline build_;
  Pipeline draw_pipeline_;
};

}  // namespace viewer
