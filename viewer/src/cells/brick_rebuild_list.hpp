#pragma once
/// @file brick_rebuild_list.hpp
/// The bricks a brick-based renderer rebuilds in a frame, uploaded into the frame slot's list buffer
/// that its build pass reads: every brick after invalidate(), else the bricks that changed.

#include <cstdint>
#include <span>

#include "granular/geometry.hpp"
#include "vulkan/host_buffer_slots.hpp"

namespace viewer {

class DescriptorSets;
class VulkanContext;

/// Per-slot brick lists bound at one binding of a renderer's descriptor sets.
class BrickRebuildList {
 public:
  /// Lists for a grid of `brick_counts` bricks, bound at `binding` of every slot's set in `sets`
  /// (which must outlive it).
  BrickRebuildList(const VulkanContext& context, granular::Int3 brick_counts, DescriptorSets& sets, int binding);
  /// Makes the next upload list every brick (a new cell buffer, a renderer switch, a reset).
  void invalidate() { rebuild_all_ = true; }
  /// Writes this frame's bricks into slot `slot`'s list (rebinding it when the buffer grew) and
  /// returns how many there are: every brick after invalidate(), else those of `changed`.
  std::uint32_t upload(int slot, std::span<const std::uint32_t> changed);

 private:
  HostBufferSlots lists_;
  DescriptorSets& sets_;
  int binding_;
  granular::Int3 brick_counts_;
  bool rebuild_all_ = true;
};

}  // namespace viewer
