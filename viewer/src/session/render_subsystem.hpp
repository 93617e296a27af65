#pragma once
/// @file render_subsystem.hpp
/// The engine subsystem that draws: its render() calls the frame function it was given.

#include <functional>
#include <utility>

#include "granular/engine/subsystem.hpp"

namespace viewer {

/// Calls `draw_frame` from render(), once per engine frame after the fixed updates.
class RenderSubsystem final : public granular::engine::Subsystem {
 public:
  /// Draws with `draw_frame`.
  explicit RenderSubsystem(std::function<void()> draw_frame)
      : granular::engine::Subsystem("render"), draw_frame_(std::move(draw_frame)) {}
  /// Draws the frame (alpha is unused: cells have no in-between states).
  void render(double) override { draw_frame_(); }

 private:
  std::function<void()> draw_frame_;
};

}  // namespace viewer
