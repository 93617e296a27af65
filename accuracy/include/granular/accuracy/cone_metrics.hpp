#pragma once
/// @file cone_metrics.hpp
/// Shape measurements of a pile of grains read from the grid: the angle of repose per azimuth and the
/// isotropy of the footprint. The first measurements of the accuracy suite.

#include <array>

#include "granular/accuracy/height_map.hpp"
#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/material.hpp"

namespace granular::accuracy {

/// Number of azimuth bins measure_cone divides the pile into (10 degrees each).
inline constexpr int kConeAzimuthBins = 36;

/// What measure_cone reports about one pile. Angles in degrees, lengths in cells.
struct ConeMetrics {
  double height_cells = 0;      ///< H = max over columns of h(x, y)
  double angle_deg = 0;         ///< mean over fitted bins of atan(-slope) of the h-against-r line fit
  double angle_spread_deg = 0;  ///< population standard deviation of the per-bin angles
  double r_half_min = 0;        ///< smallest per-bin radius at half height
  double r_half_max = 0;        ///< largest per-bin radius at half height
  double r_half_ratio = 0;      ///< r_half_max / r_half_min (1 for a round footprint, ~1.41 for a square)
  double fourfold_amplitude = 0;  ///< |sum_k r_k e^{4 i phi_k}| / sum_k r_k over bins with a half-height radius
  double onefold_amplitude = 0;   ///< the same with e^{i phi_k}: the footprint's centre is off the axis
  double twofold_amplitude = 0;   ///< the same with e^{2 i phi_k}: an elliptic footprint (e.g. x/y asymmetry)
  std::array<double, kConeAzimuthBins> bin_angle_deg{};  ///< per-bin angle (NaN where the bin was skipped)
  std::array<double, kConeAzimuthBins> bin_r_half{};     ///< per-bin radius at half height (NaN where skipped)
  int bins = 0;                 ///< bins that produced an angle (at most kConeAzimuthBins)
};

/// A cone's angle along the grid's axes and along its diagonals, where a 2x2x2 toppling rule rests
/// at 45 and 35 deg.
struct AxisDiagonalAngles {
  double axis_deg = 0;      ///< mean per-bin angle over bins centred within 10 deg of 0, 90, 180 or 270
  double diagonal_deg = 0;  ///< mean per-bin angle over bins centred within 5 deg of 45, 135, 225 or 315
  bool ok = false;          ///< false when either set of bins has no angle
};

/// The per-bin angles of `m` averaged near the axes and near the diagonals.
AxisDiagonalAngles axis_diagonal_angles(const ConeMetrics& m);

/// Measures the pile of `material` standing on the layer `floor_z` of `grid`, around the vertical
/// axis through (apex_xy_center.x, apex_xy_center.y) (z is ignored): measure_cone of the grid's
/// height_map(grid, floor_z, material), h(x, y) the number of `material` cells in the column with
/// floor_z <= z < nz. Returns all zeros when the grid holds no grain of `material` above floor_z.
ConeMetrics measure_cone(const Grid& grid, Vec3 apex_xy_center, int floor_z, Material material = Material::Granular);

/// Measures the cone whose height map is `heights` (columns of height h(x, y) <= 0 are outside it)
/// around the vertical axis through (apex_xy_center.x, apex_xy_center.y) (z is ignored). A crater
/// is measured as the cone of its depth map (the bed's level minus h).
///
/// Definitions (column (x, y) has its centre at (x + 0.5, y + 0.5)):
/// * H = max h(x, y); dx = x + 0.5 - cx, dy = y + 0.5 - cy, r = sqrt(dx^2 + dy^2),
///   phi = atan2(dy, dx) mapped to [0, 2 pi); bin k = floor(phi / (2 pi / 36)), centre angle
///   phi_k = (k + 1/2) 2 pi / 36;
/// * angle of repose per bin: the least-squares line h = a + s r over the bin's columns with
///   0.2 H <= h <= 0.8 H (bins with fewer than 3 such columns, or with all r equal, are skipped),
///   s = sum (r - r_mean)(h - h_mean) / sum (r - r_mean)^2, angle_k = atan(-s) in degrees;
///   angle_deg = mean_k angle_k, angle_spread_deg = sqrt(mean_k (angle_k - angle_deg)^2);
/// * radius at half height per bin: r_k = mean r over the bin's columns with |h - H/2| <= 1
///   (bins with no such column are skipped); r_half_min/max = min/max_k r_k, r_half_ratio =
///   max/min; fourfold_amplitude = |sum_k r_k e^{4 i phi_k}| / sum_k r_k (0 for a circle; a square
///   pyramid measures about 0.07 whatever its orientation, as the modulus removes the phase);
///   onefold_amplitude and twofold_amplitude use e^{i phi_k} and e^{2 i phi_k} likewise (an
///   ellipse of axes a > b measures about (a - b) / (a + b) in the 2-fold amplitude).
/// Returns all zeros when no column is above 0.
ConeMetrics measure_cone(const HeightMap& heights, Vec3 apex_xy_center);

}  // namespace granular::accuracy
