#pragma once
/// @file offscreen_renderer.hpp
/// Renders a World into an offscreen image with no window (tests, screenshots, benchmarks,
/// servers): frames in flight with a fence each, so the simulation of the next frame overlaps the
/// GPU work of the previous one.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "vulkan/frame_slots.hpp"
#include "vulkan/frames_in_flight.hpp"
#include "vulkan/render_target.hpp"
#include "renderers/world_renderer.hpp"

namespace viewer {

class VulkanContext;

/// An offscreen target plus a WorldRenderer and per-slot command buffers and fences.
class OffscreenRenderer {
 public:
  /// Renders `world` (which must outlive it) at `extent` with the renderer of `kind`; through
  /// `shared` (CUDA interop) when given, keeping `detail`.
  OffscreenRenderer(const VulkanContext& context, const granular::World& world, VkExtent2D extent, RendererKind kind,
                    SharedCells* shared = nullptr, const RenderDetail& detail = {});
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  /// Records and submits one frame of the world as it is now; returns without waiting for the GPU
  /// (but waits for the frame that used the same slot before).
  FrameWork render(const OrbitCamera& camera, const BrushView& brush = {});
  /// Waits for every submitted frame.
  void wait_idle() const;
  /// The latest frame's pixels (RGBA8, rows top to bottom); waits for it.
  std::vector<std::uint8_t> pixels();
  /// The GPU timings of the most recent finished frame (waits for the latest).
  GpuTimings last_timings();
  /// GPU timings of the frames that finished since the last call (collected when their slot is
  /// reused, so reading them never stalls the pipeline).
  std::vector<GpuTimings> take_finished_timings();
  /// Switches the renderer (waits for the GPU first).
  void set_kind(RendererKind kind);
  /// The world renderer.
  WorldRenderer& world_renderer() { return *renderer_; }
  /// Image size.
  VkExtent2D extent() const { return target_->extent(); }

 private:
  const VulkanContext& context_;
  std::unique_ptr<RenderTarget> target_;
  std::unique_ptr<WorldRenderer> renderer_;
  FrameSlots slots_;
  std::array<bool, kFramesInFlight> in_use_{};
  std::vector<GpuTimings> finished_;
  int slot_ = 0;
  int last_slot_ = -1;
};

}  // namespace viewer
