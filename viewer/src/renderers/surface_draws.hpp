#pragma once
/// @file surface_draws.hpp
/// The draw sequence of the raster renderers (instanced cubes, marching cubes), whose build writes,
/// per brick, one indirect command for its opaque surfaces and one for its translucent ones: the
/// opaque surfaces, the section's opaque cap, the translucent surfaces blended over them, under
/// x-ray the opaque commands again for the static materials alone (blended), and the section's
/// translucent cap. The push constants tell each draw its pass (see_inside.hpp).

#include <vulkan/vulkan.h>

#include <cstdint>

#include "renderers/renderer.hpp"

namespace viewer {

class DrawCompaction;
class Pipeline;
class SectionCap;

/// What the sequence draws with: the renderer's opaque and translucent pipelines over `set`, its
/// indirect commands compacted to the bricks that draw something (the opaque list, the translucent
/// list) and its cap.
struct SurfaceDraws {
  const Pipeline& opaque;               ///< depth-written surfaces
  const Pipeline& translucent;          ///< blended surfaces
  VkDescriptorSet set;                  ///< the frame slot's descriptor set
  const DrawCompaction& compaction;     ///< the compacted indirect draw commands
  const SectionCap& cap;                ///< the section's cap
};

/// Records the sequence for `view` into `commands`.
void record_surface_draws(VkCommandBuffer commands, const FrameView& view, const SurfaceDraws& draws);

}  // namespace viewer
