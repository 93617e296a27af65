#include "session/sandbox_tools.hpp"

#include <cstdint>
#include <algorithm>
#include <cmath>
#include <iterator>

#include "granular/errors.hpp"

namespace viewer {

const char* to_string(Tool tool) {
  switch (tool) {
    case Tool::Dig: return "dig";
    case Tool::Pour: return "pour";
    case Tool::Place: return "place";
    case Tool::Erase: return "erase";
    case Tool::Shake: return "shake";
  }
  return "?";
}

int shake_level(const granular::RuleSet& rules) { return rules.motion.enabled() ? rules.motion.max_level() : 0; }

std::vector<Tool> left_button_tools(const granular::RuleSet& rules) {
  std::vector<Tool> tools{Tool::Dig, Tool::Erase};
  if (shake_level(rules) > 0) tools.push_back(Tool::Shake);
  return tools;
}

Tool next_left_tool(Tool current, const granular::RuleSet& rules) {
  const std::vector<Tool> tools = left_button_tools(rules);
  const auto at = std::find(tools.begin(), tools.end(), current);
  if (at == tools.end()) return Tool::Dig;
  return std::next(at) == tools.end() ? tools.front() : *std::next(at);
}

std::int64_t apply_tool(granular::World& world, const ToolState& state) {
  if (!state.held || !state.target) return 0;
  const granular::Vec3 hit = *state.target;
  const double r = state.radius;
  try {
    switch (state.tool) {
      case Tool::Dig: return world.dig({hit, r}).cells_changed;
      case Tool::Pour: {
        const std::int64_t amount =
            state.pour_per_tick > 0 ? state.pour_per_tick : std::max<std::int64_t>(1, std::int64_t(r * r * r));
        const granular::Vec3 above{hit.x, hit.y, hit.z + r + 2.0};
        return world.pour(above, r, state.material, amount).cells_changed;
      }
      case Tool::Place: return world.paint(granular::Sphere{state.target_in_front.value_or(hit), r}, state.material).cells_changed;
      case Tool::Erase: return world.paint(granular::Sphere{hit, r}, granular::Material::Void).cells_changed;
      case Tool::Shake: {
        const int level = shake_level(world.rules());
        return level > 0 ? world.shake(granular::Sphere{hit, r}, level).cells_shaken : 0;
      }
    }
  } catch (const granular::InvalidArgument&) {
    // The brush lies wholly outside the grid (e.g. pouring above the top): nothing to do.
  }
  return 0;
}

ToolSubsystem::ToolSubsystem(granular::World& world, std::vector<granular::Emitter> emitters)
    : granular::engine::Subsystem("tools"), world_(world), emitters_(std::move(emitters)) {}

void ToolSubsystem::fixed_update(double) {
  if (state_.held) {
    cells_changed_ += apply_tool(world_, state_);
    ++applications_;
  }
  if (!emitters_.empty() && (!running_ || running_())) granular::run_emitters(world_, emitters_);
}

void ToolSubsystem::apply_once() {
  ToolState once = state_;
  once.held = true;
  cells_changed_ += apply_tool(world_, once);
  ++applications_;
}

}  // namespace viewer
