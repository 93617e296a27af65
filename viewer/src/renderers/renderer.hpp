#pragma once
/// @file renderer.hpp
/// The interface every way of drawing the cell buffer implements (instanced cubes, marching cubes,
/// ray march). A frame calls prepare() outside the render pass, then draw() inside it.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>

#include "vulkan/render_target.hpp"
#include "section/see_inside.hpp"
#include "renderers/view_constants.hpp"

namespace viewer {

/// Which renderer.
enum class RendererKind {
  Cubes,     ///< instanced cubes of the surface cells
  Marching,  ///< marching-cubes surfaces of the opaque, liquid and gas densities
  Raymarch,  ///< compute-shader DDA through the cell buffer, no geometry
};

/// "cubes", "marching" or "raymarch".
const char* to_string(RendererKind kind);

/// How much detail the geometry renderers keep where cells are small on the image.
struct RenderDetail {
  /// Marching cubes meshes a brick with a cube per 2x2x2 cells (a quarter of the triangles) where
  /// its cells cover fewer than this many pixels of the image's height (brick_detail.hpp); 0 keeps
  /// every brick at a cube per cell.
  float coarse_below_pixels = 1.0f;
};

/// What a renderer needs to know about the frame being recorded.
struct FrameView {
  int slot = 0;                  ///< frame-in-flight slot (selects per-frame buffers)
  ViewConstants raster;          ///< constants for raster shaders (matrix = view-projection)
  ViewConstants inverse;         ///< the same with matrix = inverse view-projection (ray march)
  SeeInside inside;              ///< the section and x-ray (already in raster.grid.w and inverse.grid.w)
  VkImage target_image = VK_NULL_HANDLE;  ///< the colour image the frame ends in
  VkImageLayout target_layout_before = VK_IMAGE_LAYOUT_UNDEFINED;  ///< its layout before the frame
  VkExtent2D extent{};           ///< its size
};

/// A renderer of the cell buffer.
class Renderer {
 public:
  /// Destroys the renderer (the device must be idle).
  virtual ~Renderer() = default;
  /// Which renderer this is.
  virtual RendererKind kind() const = 0;
  /// Makes the next prepare() rebuild every brick (after a switch or when the cells were replaced).
  virtual void invalidate() = 0;
  /// Records the work before the render pass: rebuilding the geometry of `changed_bricks` (already
  /// grown by their neighbours), or the ray march. Returns the bricks rebuilt.
  virtual std::uint64_t prepare(VkCommandBuffer commands, const FrameView& view,
                                std::span<const std::uint32_t> changed_bricks) = 0;
  /// How the render pass must treat the colour attachment after prepare().
  virtual ColorLoad color_load() const { return ColorLoad::Clear; }
  /// Records the draw inside the render pass.
  virtual void draw(VkCommandBuffer commands, const FrameView& view) = 0;
};

}  // namespace viewer
