#pragma once
/// @file orifice_tank.hpp
/// The vessel of the silo and Torricelli tests: a cylinder with a flat bottom plate pierced by a
/// centred round orifice, over a sink where what falls through is removed and counted.

#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/material.hpp"

namespace granular::accuracy {

/// A cylindrical tank: a sink of kSink layers at the bottom (all but its top 2 cleared every tick,
/// so a cell is counted once it has fallen clear of the plate, however fast it falls), a solid plate
/// kPlate thick with a centred round orifice of diameter `orifice`, a solid shell outside radius
/// `radius`, and `fill` layers of a material above the plate.
struct OrificeTank {
  int orifice;  ///< the orifice's diameter (cells)
  int radius;   ///< the shell's inner radius (cells)
  int fill;     ///< layers filled above the plate
  static constexpr int kSink = 8, kPlate = 2;
  /// The first layer above the plate.
  int plate_top() const { return kSink + kPlate; }
  /// The grid's extent: 2 cells of shell around the cylinder, 4 void layers above the fill.
  Int3 size() const { return {2 * radius + 4, 2 * radius + 4, plate_top() + fill + 4}; }
  /// True when column (x, y) lies inside the shell.
  bool inside(int x, int y) const;
  /// Columns inside the shell: the tank's cross-section in cells.
  int area() const;
  /// The layers of the sink that are cleared every tick.
  Box sink() const { return {{0, 0, 0}, {size().x, size().y, kSink - 2}}; }
  /// The tank's grid, filled with `material`.
  Grid build(Material material) const;
};

}  // namespace granular::accuracy
