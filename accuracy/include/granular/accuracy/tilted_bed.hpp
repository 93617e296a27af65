#pragma once
/// @file tilted_bed.hpp
/// The tilt test's bed: a walled box holding a bed of sand inclined along x, and the angle of its
/// surface. The suite's hysteresis test tilts it step by step; the entrain lever's tests use it at
/// one angle.

#include "granular/geometry.hpp"
#include "granular/grid.hpp"

namespace granular::accuracy {

/// A walled box (solid floor at z = 0, walls at x = 0, x = nx - 1, y = 0, y = ny - 1) with sand over x
/// in [1, 1 + slope_length) rising towards x = 1 and a void run-out beyond.
struct TiltedBed {
  int slope_length = 32;  ///< columns of the slope along x
  int width = 12;         ///< cells of the bed along y, between the walls
  int runout = 48;        ///< void columns after the slope
  int base = 2;           ///< cells of sand under the slope's foot
  double max_deg = 62;    ///< the steepest angle the box is tall enough for

  /// The box's size.
  Int3 size() const;
  /// The box with the bed inclined at `deg` degrees: column 1 + i holds base + round((slope_length -
  /// i - 0.5) tan(deg)) cells of sand.
  Grid build(double deg) const;
};

/// The surface angle of a tilted bed in degrees: the least-squares line of the mean column height
/// (over y, between the walls) against x, over the columns between 20% and 80% of the highest; NaN
/// when fewer than two columns are in that band.
double tilted_bed_slope_deg(const Grid& grid, const TiltedBed& bed);

/// The fraction of `before`'s sand cells that hold no sand in `after` (a grid of the same size):
/// how much of a bed an avalanche moved.
double moved_fraction(const Grid& before, const Grid& after);

}  // namespace granular::accuracy
