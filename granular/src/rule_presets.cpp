#include "granular/rule_presets.hpp"

#include <utility>

#include "granular/errors.hpp"
#include "granular/material.hpp"
#include "step/motion_block.hpp"
#include "step/paper_rule.hpp"

namespace granular {

namespace {

/// The inertial presets' motion model for `substeps` sub-steps per tick: every moving grain may roll,
/// a topple always gains a level and a roll costs one with chance 160/256, which puts the full-size
/// poured cone's angle at 34.6 degrees, near dry sand's 33 (tuned on the accuracy suite's cone on
/// the GPU: 128 gives 29.4, 192 gives 36.4).
constexpr MotionParams inertial_motion(int substeps) {
  return MotionParams{.substeps = substeps, .topple_gain = 256, .roll_cost = 160, .roll_chance = 256};
}

RuleSet make_preset(std::string name, std::string description, std::uint32_t version, bool random_symmetry,
                    bool random_axis_order, MotionParams motion = {}) {
  RuleSet r;
  r.name = std::move(name);
  r.description = std::move(description);
  r.version = version;
  r.random_symmetry = random_symmetry;
  r.random_axis_order = random_axis_order;
  r.motion = motion;
  r.transition = motion.enabled() ? &motion_transition : &paper_transition;
  r.device_rule = motion.enabled() ? "motion" : "paper";
  return r;
}

}  // namespace

Transition paper_transition(const BlockCells& cells) { return rules::paper_rule(encode_key(cells)); }

Transition motion_transition(const BlockCells& cells) { return motion::motion_rule(encode_key(cells)); }

std::shared_ptr<const RuleSet> make_rule_set(std::string_view name) {
  if (name == "paper")
    return std::make_shared<const RuleSet>(
        make_preset("paper", "gravity then flow, fixed preference order (the paper's rules)", 1, false, false));
  if (name == "isotropic")
    return std::make_shared<const RuleSet>(make_preset(
        "isotropic", "the paper's rules under a random horizontal symmetry per block and tick and a random offset order per cycle",
        2, true, true));
  if (name == "d4")
    return std::make_shared<const RuleSet>(make_preset(
        "d4", "the paper's rules under a random horizontal symmetry per block and tick, the paper's offset cycle", 1, true,
        false));
  if (name == "inertial")
    return std::make_shared<const RuleSet>(make_preset(
        "inertial",
        "isotropic plus inertia and rolling: 16 sub-steps per tick, grains accelerate in free fall and roll on",
        1, true, true, inertial_motion(16)));
  if (name == "inertial-24")
    return std::make_shared<const RuleSet>(make_preset(
        "inertial-24", "inertial with 24 sub-steps per tick: a top speed of 23 cells per tick instead of 15, for 1.5 times the cost", 1, true, true,
        inertial_motion(24)));
  std::string valid;
  for (const auto& n : rule_preset_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw InvalidArgument("unknown rule set '" + std::string(name) + "'; valid rule sets: " + valid);
}

std::vector<std::string> rule_preset_names() { return {"paper", "isotropic", "d4", "inertial", "inertial-24"}; }

}  // namespace granular
