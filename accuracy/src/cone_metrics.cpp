#include "granular/accuracy/cone_metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

namespace granular::accuracy {

namespace {

/// Running sums of one azimuth bin.
struct BinSums {
  double n = 0, sr = 0, sh = 0, srr = 0, srh = 0;  // line-fit sums over 0.2 H <= h <= 0.8 H
  double half_n = 0, half_r = 0;                   // columns with |h - H/2| <= 1
};

}  // namespace

ConeMetrics measure_cone(const Grid& grid, Vec3 apex_xy_center, int floor_z, Material material) {
  return measure_cone(height_map(grid, floor_z, material), apex_xy_center);
}

ConeMetrics measure_cone(const HeightMap& heights, Vec3 apex_xy_center) {
  double height = 0;
  for (double v : heights.h) height = std::max(height, v);
  ConeMetrics m;
  m.bin_angle_deg.fill(std::numeric_limits<double>::quiet_NaN());
  m.bin_r_half.fill(std::numeric_limits<double>::quiet_NaN());
  if (height <= 0) return m;
  m.height_cells = height;

  const double two_pi = 2 * std::numbers::pi;
  const double bin_width = two_pi / kConeAzimuthBins;
  const double lo = 0.2 * height, hi = 0.8 * height, half = 0.5 * height;
  std::array<BinSums, kConeAzimuthBins> bins{};
  for (int y = 0; y < heights.ny; ++y)
    for (int x = 0; x < heights.nx; ++x) {
      const double hv = heights.at(x, y);
      if (hv <= 0) continue;
      const double dx = x + 0.5 - apex_xy_center.x, dy = y + 0.5 - apex_xy_center.y;
      const double r = std::hypot(dx, dy);
      double phi = std::atan2(dy, dx);
      if (phi < 0) phi += two_pi;
      const int k = std::min(int(phi / bin_width), kConeAzimuthBins - 1);
      BinSums& b = bins[std::size_t(k)];
      if (hv >= lo && hv <= hi) {
        b.n += 1;
        b.sr += r;
        b.sh += hv;
        b.srr += r * r;
        b.srh += r * hv;
      }
      if (std::abs(hv - half) <= 1) {
        b.half_n += 1;
        b.half_r += r;
      }
    }

  std::vector<double> angles;
  double r_sum = 0;
  std::complex<double> r_one{0, 0}, r_two{0, 0}, r_four{0, 0};

  m.r_half_min = 0;
  m.r_half_max = 0;
  bool any_half = false;
  for (int k = 0; k < kConeAzimuthBins; ++k) {
    const BinSums& b = bins[std::size_t(k)];
    if (b.n >= 3) {
      const double var = b.srr - b.sr * b.sr / b.n;
      if (var > 1e-12) {
        const double slope = (b.srh - b.sr * b.sh / b.n) / var;
        angles.push_back(std::atan(-slope) * 180 / std::numbers::pi);
        m.bin_angle_deg[std::size_t(k)] = angles.back();
      }
    }
    if (b.half_n > 0) {
      const double r = b.half_r / b.half_n;
      const double phi = (k + 0.5) * bin_width;
      r_sum += r;
      m.bin_r_half[std::size_t(k)] = r;
      r_one += r * std::polar(1.0, phi);
      r_two += r * std::polar(1.0, 2 * phi);
      r_four += r * std::polar(1.0, 4 * phi);
      m.r_half_min = any_half ? std::min(m.r_half_min, r) : r;
      m.r_half_max = any_half ? std::max(m.r_half_max, r) : r;
      any_half = true;
    }
  }
  m.bins = int(angles.size());
  if (!angles.empty()) {
    double mean = 0;
    for (double a : angles) mean += a;
    mean /= double(angles.size());
    double var = 0;
    for (double a : angles) var += (a - mean) * (a - mean);
    m.angle_deg = mean;
    m.angle_spread_deg = std::sqrt(var / double(angles.size()));
  }
  if (any_half && m.r_half_min > 0) m.r_half_ratio = m.r_half_max / m.r_half_min;
  if (r_sum > 0) {
    m.onefold_amplitude = std::abs(r_one) / r_sum;
    m.twofold_amplitude = std::abs(r_two) / r_sum;
    m.fourfold_amplitude = std::abs(r_four) / r_sum;
  }
  return m;
}

AxisDiagonalAngles axis_diagonal_angles(const ConeMetrics& m) {
  double axis_sum = 0, diagonal_sum = 0;
  int axis_n = 0, diagonal_n = 0;
  for (int k = 0; k < kConeAzimuthBins; ++k) {
    const double a = m.bin_angle_deg[std::size_t(k)];
    if (!std::isfinite(a)) continue;
    const double phi = (k + 0.5) * 360.0 / kConeAzimuthBins;
    const double from_axis = std::abs(std::remainder(phi, 90.0));
    if (from_axis <= 10) {
      axis_sum += a;
      ++axis_n;
    } else if (std::abs(from_axis - 45) <= 5) {
      diagonal_sum += a;
      ++diagonal_n;
    }
  }
  AxisDiagonalAngles r;
  r.ok = axis_n > 0 && diagonal_n > 0;
  if (r.ok) {
    r.axis_deg = axis_sum / axis_n;
    r.diagonal_deg = diagonal_sum / diagonal_n;
  }
  return r;
}

}  // namespace granular::accuracy
