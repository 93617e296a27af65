#pragma once
/// @file rule_presets.hpp
/// The shipped rule sets.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "granular/rule_set.hpp"

namespace granular {

/// The paper's rules: gravity (a grain above void falls), then flow (a supported grain in the top
/// layer topples diagonally down into a void whose column above is void too), with a fixed order
/// of preference (+/-x neighbour, then y, then diagonal). Deterministic; piles at 45 degrees.
Transition paper_transition(const BlockCells& cells);

/// The motion model's rule (motion.hpp): the paper's rule on void, obstacle and grain, plus a
/// roller state (table code 3) that also rolls sideways onto a level neighbour.
Transition motion_transition(const BlockCells& cells);

/// Looks up a preset by name: "paper" (the paper's deterministic rules and offset cycle),
/// "isotropic" (the same table under a random horizontal symmetry per block and tick, and a random
/// offset order per 8-tick cycle, so heaps come out round) or "d4" (the random symmetry alone, on
/// the paper's cycle: isotropic before the offset order was drawn, kept for comparison).
/// Throws InvalidArgument naming the valid presets for an unknown name.
std::shared_ptr<const RuleSet> make_rule_set(std::string_view name);

/// Names of every preset, in a stable order.
std::vector<std::string> rule_preset_names();

}  // namespace granular
