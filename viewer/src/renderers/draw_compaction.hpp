#pragma once
/// @file draw_compaction.hpp
/// The indirect draws of a brick-based renderer (cubes, marching cubes) compacted to the bricks
/// that draw something (shaders/draw_compact.comp): the draw pass then issues one command per such
/// brick with vkCmdDrawIndirectCount, not one per brick of the grid, most of which are empty. The
/// opaque list goes front to back from the eye (the depth test then rejects covered surfaces before
/// they are shaded), the translucent list back to front.

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>

#include "vulkan/gpu_buffer.hpp"
#include "vulkan/pipeline_builder.hpp"
#include "renderers/view_constants.hpp"

namespace viewer {

class VulkanContext;

/// Compacts `draws` (2 x bricks draw commands: the opaque list, then the translucent one) into
/// lists of the commands that draw something, ordered from the eye.
class DrawCompaction {
 public:
  /// Compaction of `draws` (which must outlive it), written by a build pass for `bricks` bricks:
  /// VkDrawIndirectCommand, or with `indices` (which must outlive it) VkDrawIndexedIndirectCommand
  /// drawing from that index buffer (32-bit indices).
  DrawCompaction(const VulkanContext& context, const GpuBuffer& draws, std::uint32_t bricks,
                 const GpuBuffer* indices = nullptr);

  /// Records the compaction for `view`'s eye when the build pass rewrote draws (`rebuilt`) or the
  /// eye moved to another brick since the last one; otherwise the lists stand. After the build
  /// pass's writes to the draws are made visible to compute shaders, and before the draw pass (this
  /// adds the barriers: earlier draws' indirect reads before its writes, its writes before the next).
  void record(VkCommandBuffer commands, const ViewConstants& view, bool rebuilt);

  /// Draws list `list` (0 opaque, 1 translucent) with the bound graphics pipeline.
  void draw(VkCommandBuffer commands, int list) const;

 private:
  std::uint32_t bricks_;
  const GpuBuffer* indices_;      ///< the index buffer of indexed commands, or null
  std::uint32_t command_bytes_;   ///< sizeof the command type
  std::uint32_t groups_;  ///< workgroups a list
  std::array<int, 3> eye_brick_{};  ///< the eye's brick at the last compaction
  bool compacted_ = false;          ///< whether a compaction was recorded
  GpuBuffer compact_;     ///< the compacted lists, each at the place of its full list
  GpuBuffer group_counts_;
  GpuBuffer draw_counts_;  ///< the two lists' lengths
  DescriptorSets sets_;
  Pipeline pass_;
};

}  // namespace viewer
