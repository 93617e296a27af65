#pragma once
/// @file sandbox_tools.hpp
/// The player's tools as an engine subsystem: on every fixed update it applies the held tool at the
/// picked point (so pouring runs at a steady rate whatever the frame rate) and runs the scene's
/// emitters. Every tool is one granular::World call.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "granular/engine/subsystem.hpp"
#include "granular/geometry.hpp"
#include "granular/material.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"

namespace viewer {

/// What the brush does.
enum class Tool {
  Dig,    ///< World::dig: removes grains in the sphere
  Pour,   ///< World::pour: emits cells of the chosen material above the point
  Place,  ///< World::paint(sphere, chosen material) in front of the hit face: builds structure
  Erase,  ///< World::paint(sphere, Void): erases everything, solid included
  Shake,  ///< World::shake(sphere, shake_level(rules)): sets the grains and liquids in the sphere moving
};

/// "dig", "pour", "place", "erase", "shake".
const char* to_string(Tool tool);

/// The motion level the shake tool sets under `rules`: the highest they allow
/// (MotionParams::max_level()), which stirs a slope the most; 0 when they have no motion model, so
/// that World::shake would refuse and the sandbox offers no shake tool.
int shake_level(const granular::RuleSet& rules);

/// The tools the left button offers under `rules`, in the order Tab cycles through them: dig, erase,
/// and shake where the rules have a motion model.
std::vector<Tool> left_button_tools(const granular::RuleSet& rules);

/// The left button's tool after `current` in Tab's cycle under `rules`; dig when `current` is not
/// one of left_button_tools(rules).
Tool next_left_tool(Tool current, const granular::RuleSet& rules);

/// The brush and what it is doing this frame.
struct ToolState {
  Tool tool = Tool::Dig;                                  ///< active tool
  double radius = 4.0;                                    ///< brush radius (cells)
  granular::Material material = granular::Material::Granular;  ///< the chosen material: Pour emits it, Place paints it
  std::int64_t pour_per_tick = 0;                         ///< cells poured per fixed update (0: brush volume / 4)
  bool held = false;                                      ///< the button is down
  std::optional<granular::Vec3> target;                   ///< the picked surface point, if the cursor hits
  std::optional<granular::Vec3> target_in_front;          ///< centre of the void cell in front of the hit face
};

/// Applies the tools and the scene's emitters once per fixed update. Borrows the world.
class ToolSubsystem final : public granular::engine::Subsystem {
 public:
  /// Acts on `world` with the scene's `emitters`.
  ToolSubsystem(granular::World& world, std::vector<granular::Emitter> emitters);
  /// Applies the held tool, then the emitters (while running()).
  void fixed_update(double dt) override;
  /// Makes the emitters pour only in fixed updates where `running` says the world steps (the
  /// simulation is not paused), so that a paused world stays as it is; by default they always pour.
  void set_running(std::function<bool()> running) { running_ = std::move(running); }
  /// Applies the tool once now at the target, held or not (a click shorter than a fixed update).
  void apply_once();
  /// The brush (the input code writes it every frame).
  ToolState& state() { return state_; }
  /// Cells changed by tools since construction (for the shake tool, the cells it set moving).
  std::int64_t cells_changed() const { return cells_changed_; }
  /// Times a tool was applied (by fixed_update while held, or by apply_once) since construction.
  std::int64_t applications() const { return applications_; }

 private:
  granular::World& world_;
  std::vector<granular::Emitter> emitters_;
  std::function<bool()> running_;  ///< empty: always running
  ToolState state_;
  std::int64_t cells_changed_ = 0;
  std::int64_t applications_ = 0;
};

/// Applies `state`'s tool once to `world` at its target; returns the cells changed, for Shake the
/// cells set moving (0 when there is no target, the button is up, or the tool is Shake and the
/// world's rules have no motion model).
std::int64_t apply_tool(granular::World& world, const ToolState& state);

}  // namespace viewer
