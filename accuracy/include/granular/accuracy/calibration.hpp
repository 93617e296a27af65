#pragma once
/// @file calibration.hpp
/// Physical units for the automaton: the size of a cell and the length of a tick.
///
/// The tick length is chosen so that a fall over the calibration height H_c takes the physical
/// time: dt = sqrt(2 d / (g H_c)) when the fall takes one tick per cell.
/// * Rules without a motion model (paper, isotropic, d4) move a grain at most one cell per tick, so
///   a fall of H cells takes H ticks instead of sqrt(2 H d / g): H_c = 64, and shorter falls are too
///   slow, longer ones too fast; the free-fall test measures by how much.
/// * With the motion model a grain falling from rest covers t^2 cells after t ticks (up to its top
///   speed), which is free fall with g = 2 d / dt^2: H_c = 1 makes that g the real one.

#include <string>

#include "granular/rule_set.hpp"

namespace granular::accuracy {

/// Cell size, tick length and gravity, as stated in every suite output.
struct Calibration {
  double cell_m = 0.005;           ///< cell edge d in metres (a 5 mm voxel of sand)
  double gravity = 9.81;           ///< g in m/s^2
  double calibration_cells = 64;   ///< H_c: the fall height whose duration is matched exactly
  double bulk_density = 1500;      ///< kg/m^3 of a cell full of sand (dry sand's bulk density)
  /// dt = sqrt(2 d / (g H_c)) in seconds.
  double tick_s() const;
  /// Mass of one grain cell in kg (bulk_density d^3).
  double cell_kg() const;
  /// g in cells per tick^2 (gravity dt^2 / d): 2 / H_c.
  double gravity_cells() const;
  /// One human-readable line naming d, dt, g and H_c.
  std::string describe() const;
};

/// The calibration of a rule set (see the file comment): H_c = 64 cells for one step per tick,
/// H_c = 1 for the motion model.
Calibration calibration_for(const RuleSet& rules);

}  // namespace granular::accuracy
