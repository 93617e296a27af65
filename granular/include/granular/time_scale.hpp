#pragma once
/// @file time_scale.hpp
/// How long a tick lasts in physical time: the calibration that makes the rules' free fall follow
/// gravity (docs/ACCURACY.md, "Calibration").

#include "granular/rule_set.hpp"

namespace granular {

/// Standard gravity in m/s^2.
inline constexpr double kStandardGravity = 9.81;

/// The gravity a rule set's free fall follows, in cells per tick^2: 2 with the motion model (a grain
/// falling from rest covers t^2 cells in t ticks), 2 / 64 without it (a grain falls one cell per
/// tick, so the tick is calibrated on a 64-cell fall, which then takes its physical time).
double gravity_cells_per_tick2(const RuleSet& rules);

/// The physical length in seconds of one tick of `rules` for cells of edge `cell_m` metres under
/// `gravity` m/s^2: sqrt(gravity_cells_per_tick2 * cell_m / gravity). For 5 mm cells: 31.9 ms with
/// the motion model, 3.99 ms without. A world stepped at 1 / tick_seconds ticks per second runs in
/// real time.
double tick_seconds(const RuleSet& rules, double cell_m = 0.005, double gravity = kStandardGravity);

}  // namespace granular
