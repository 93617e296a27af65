#pragma once
/// @file calibration.hpp
/// Physical units for the automaton: the size of a cell and the length of a tick.
///
/// The paper's rules move a grain at most one cell per tick, so a fall of H cells takes H ticks
/// instead of sqrt(2 H d / g). The tick length is chosen so that a fall over the calibration height
/// H_c takes the physical time: H_c dt = sqrt(2 H_c d / g), i.e. dt = sqrt(2 d / (g H_c)). Shorter
/// falls are then too slow and longer ones too fast; the free-fall test measures by how much.

#include <string>

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
  /// One human-readable line naming d, dt, g and H_c.
  std::string describe() const;
};

}  // namespace granular::accuracy
