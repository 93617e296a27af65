#pragma once
/// @file rule_presets.hpp
/// The shipped rule sets: one registry, enumerated by rule_preset_names() (the CLI, the accuracy
/// suite and the sandbox list presets from it).

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "granular/rule_set.hpp"

namespace granular {

/// The paper's rules on a material table: gravity (a granular cell above void falls), then flow (a
/// supported granular cell in the top layer topples diagonally down into a void whose column above is
/// void too), with a fixed order of preference (+/-x neighbour, then y, then diagonal); static
/// materials never move. Deterministic; piles at 45 degrees.
Transition paper_transition(const BlockCells& cells, const MaterialTable& materials);

/// The motion model's rule (motion.hpp) on table codes: the paper's rule on void, obstacle and grain,
/// plus a roller code (3) that also rolls sideways onto a level neighbour. `materials` is unused: the
/// step maps materials to codes (motion_block.hpp).
Transition motion_transition(const BlockCells& codes, const MaterialTable& materials);

/// The shipped material table: void (0), solid (1, static), granular (2, sand, rolling as `grain`
/// says), liquid (3, water), gas (4), gravel (5, granular: denser than sand and rolling less, so its
/// heap is steeper) and two static states (6, 7) a game may give materials of its own; density
/// order gas < void < water < sand < gravel. With `grain` all zero (the one-step presets) no material
/// has motion parameters.
MaterialTable default_materials(GrainMotion grain = {});

/// A preset by name, as a value a game may copy and change: "paper" (the paper's deterministic rules
/// and offset cycle), "isotropic" (the same table under a random horizontal symmetry per block and
/// tick, and a random offset order per 8-tick cycle, so heaps come out round), "d4" (the random
/// symmetry alone, on the paper's cycle), "inertial" (isotropic plus the motion model: 16 sub-steps
/// per tick, inertia and rolling), "inertial-24" (24 sub-steps), "inertial-24-entrain" (rolling grains
/// set the grains at rest on step edges moving, so slopes avalanche), "inertial-24-flow" (the default:
/// inertial-24-entrain with grains that roll or topple moving at most one cell a tick, so a pile's
/// angle does not depend on its size) and "inertial-24-columns" (inertial-24-flow with grains in free
/// fall falling as columns, so a released block falls as a block).
/// Throws InvalidArgument naming the valid presets for an
/// unknown name.
RuleSet preset(std::string_view name);

/// preset(name), shared.
std::shared_ptr<const RuleSet> make_rule_set(std::string_view name);

/// Names of every preset, in a stable order: the registry's enumeration.
std::vector<std::string> rule_preset_names();

}  // namespace granular
