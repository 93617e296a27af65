#pragma once
/// @file world_renderer.hpp
/// Records one frame of a World: bring the cell buffer up to date (upload of the changed bricks),
/// let the active renderer rebuild what changed, then draw it (and any overlay) in the render pass.
/// Timestamp queries split the frame's GPU time into upload, build and draw.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>

#include "session/camera.hpp"
#include "cells/cell_buffer.hpp"
#include "vulkan/frames_in_flight.hpp"
#include "cells/material_palette.hpp"
#include "renderers/renderer.hpp"

namespace granular {
class World;
}

namespace viewer {

class VulkanContext;
class RenderTarget;
class SharedCells;

/// GPU time of one frame's phases, in milliseconds (0 where the device has no timestamps).
struct GpuTimings {
  double upload_ms = 0;  ///< cell upload (staging copy or brick scatter)
  double build_ms = 0;   ///< instance build / meshing / ray march
  double draw_ms = 0;    ///< the render pass (draw + overlay)
};

/// What a frame did on the CPU side.
struct FrameWork {
  std::uint64_t bricks_uploaded = 0;  ///< bricks whose cells were uploaded
  std::uint64_t bytes_uploaded = 0;   ///< bytes copied host to device
  std::uint64_t bricks_rebuilt = 0;   ///< bricks whose geometry was rebuilt
};

/// The brush highlight drawn by the raster renderers.
struct BrushView {
  bool visible = false;       ///< draw it
  glm::vec3 center{0.0f};     ///< centre (cells)
  float radius = 0;           ///< radius (cells)
};

/// Renders one World (which must outlive it) into targets compatible with `target_pass`.
class WorldRenderer {
 public:
  /// Creates the cell buffer for `world`, the palette of its material table (World::rules()) and
  /// the renderer of `kind`. With `shared` (CUDA interop, outliving this), each frame snapshots the
  /// shared cells on the device instead of uploading. Renderers keep `detail`.
  WorldRenderer(const VulkanContext& context, const granular::World& world, VkRenderPass target_pass, RendererKind kind,
                SharedCells* shared = nullptr, const RenderDetail& detail = {});
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~WorldRenderer();
  WorldRenderer(const WorldRenderer&) = delete;
  WorldRenderer& operator=(const WorldRenderer&) = delete;

  /// Uses `target_pass` for renderers created from now on (after the swapchain was recreated;
  /// existing pipelines stay valid, the new pass being compatible).
  void set_target_pass(VkRenderPass target_pass) { target_pass_ = target_pass; }
  /// Switches the renderer (created on first use).
  void set_kind(RendererKind kind);
  /// Frees the renderers made earlier that are not drawing now (waits for the device first).
  void release_inactive();
  /// The active renderer.
  RendererKind kind() const { return active_->kind(); }
  /// The cell buffer.
  const CellBuffer& cells() const { return *cells_; }
  /// Draws the frames recorded from now on with `inside`'s section plane and x-ray. The section
  /// rebuilds nothing (the renderers apply it when drawing); a change of x-ray rebuilds the active
  /// renderer's bricks once (the builds list the faces a static material hides only under x-ray).
  void set_see_inside(const SeeInside& inside);
  /// The section plane and x-ray of the frames recorded now.
  const SeeInside& see_inside() const { return inside_; }

  /// Records the frame of slot `slot` into `commands` for image `image_index` of `target`.
  /// `overlay` (may be empty) records more draws inside the render pass (the HUD).
  FrameWork record(VkCommandBuffer commands, int slot, const RenderTarget& target, std::uint32_t image_index,
                   VkImageLayout image_layout_before, const OrbitCamera& camera, const BrushView& brush,
                   const std::function<void(VkCommandBuffer)>& overlay = {});
  /// The GPU timings of slot `slot`'s last frame; call only after that frame has finished.
  GpuTimings timings(int slot) const;

 private:
  Renderer& renderer_of(RendererKind kind);

  const VulkanContext& context_;
  const granular::World& world_;
  VkRenderPass target_pass_;
  SharedCells* shared_;
  RenderDetail detail_;
  std::unique_ptr<CellBuffer> cells_;
  MaterialPalette palette_;
  std::array<std::unique_ptr<Renderer>, 3> renderers_;
  Renderer* active_ = nullptr;
  SeeInside inside_;
  bool uploaded_once_ = false;
  std::uint64_t uploaded_version_ = 0;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  std::array<bool, kFramesInFlight> queries_written_{};
};

}  // namespace viewer
