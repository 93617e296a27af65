#pragma once
/// @file raymarch_renderer.hpp
/// The ray-march renderer: a compute shader walks each pixel's ray through the cell buffer and
/// writes the colour into a storage image, which is blitted into the frame's colour image; no
/// instance build, no rasterised geometry (for GPUs where rasterisation is the limit, and 1024^3).
/// Rays stop at the first opaque cell and see through liquids and gases, which absorb along the
/// path; colours come from the world's material table (MaterialPalette). Rays walk only the cells a
/// section plane keeps, entering through the plane; under x-ray static cells absorb like a medium.
/// Its only per-brick state is one occupancy flag per brick (rebuilt for changed bricks), which
/// lets rays cross empty bricks in one step.

#include <cstdint>

#include "vulkan/device_image.hpp"
#include "vulkan/gpu_buffer.hpp"
#include "granular/geometry.hpp"
#include "cells/brick_rebuild_list.hpp"
#include "vulkan/pipeline_builder.hpp"
#include "renderers/renderer.hpp"

namespace viewer {

class VulkanContext;
class CellBuffer;
class MaterialPalette;

/// The ray-march renderer.
class RaymarchRenderer final : public Renderer {
 public:
  /// Reads `cells` and `palette` (which must outlive it).
  RaymarchRenderer(const VulkanContext& context, const CellBuffer& cells, const MaterialPalette& palette);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~RaymarchRenderer() override;

  /// See Renderer (renderer.hpp).
  RendererKind kind() const override { return RendererKind::Raymarch; }
  /// See Renderer (renderer.hpp).
  void invalidate() override { rebuild_.invalidate(); }
  /// See Renderer (renderer.hpp).
  std::uint64_t prepare(VkCommandBuffer commands, const FrameView& view,
                        std::span<const std::uint32_t> changed_bricks) override;
  /// See Renderer (renderer.hpp).
  ColorLoad color_load() const override { return ColorLoad::Load; }
  /// See Renderer (renderer.hpp).
  void draw(VkCommandBuffer, const FrameView&) override {}

 private:
  void ensure_image(VkExtent2D extent);
  void release_image();

  const VulkanContext& context_;
  granular::Int3 brick_counts_;
  GpuBuffer occupancy_;
  DescriptorSets sets_;
  BrickRebuildList rebuild_;  ///< after sets_: binds its lists there
  Pipeline occupancy_pass_;
  Pipeline march_;
  VkExtent2D extent_{};
  DeviceImage image_;  ///< the storage image the march writes, at extent_
};

}  // namespace viewer
