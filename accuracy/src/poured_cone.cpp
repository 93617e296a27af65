#include "poured_cone.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "granular/accuracy/pour_cone.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// A footprint r(phi) = r0 (1 + A cos(m phi)) has r_max / r_min = (1 + A) / (1 - A); the suite's
/// target r_max / r_min <= 1.05 thus bounds each Fourier amplitude by A = 0.05 / 2.05.
constexpr double kRatioTarget = 1.05;
constexpr double kAmplitudeTarget = (kRatioTarget - 1) / (kRatioTarget + 1);

}  // namespace

TestReport run_poured_cone(const SuiteOptions& o, const ConeTarget& target) {
  const int floor = o.quick ? 96 : 256, height = o.quick ? 64 : 128;
  const double spout = o.quick ? 2.0 : 4.0;
  const std::uint64_t pour_ticks = o.quick ? 4000 : 16000, settle_ticks = o.quick ? 4000 : 20000;
  const std::int64_t per_tick = o.quick ? 60 : 400;
  std::string scene = std::to_string(floor) + "^2 floor x " + std::to_string(height) + " cells, spout of radius " +
                      std::to_string(int(spout)) + " at the centre, " + std::to_string(pour_ticks) + " ticks of pouring (at most " +
                      std::to_string(per_tick) + " grains per tick) then settling";
  TestReport r = open_report(o, target.test, target.title, scene);
  const PourResult p =
      pour_cone(test_world_def(o, {floor, floor, height}), floor, height, per_tick, pour_ticks, settle_ticks, spout, target.material);
  const ConeMetrics& m = p.metrics;
  r.seconds = p.seconds;
  r.ticks = p.ticks;
  r.cell_updates = double(floor) * floor * height * double(p.ticks);
  r.conserved = p.conserved;
  const std::string round = "ideal: a poured cone of dry grains is round (target r_max/r_min <= 1.05)";
  r.metrics.push_back({"angle_of_repose", "deg", m.angle_deg, target.repose_deg, 2.0, target.source});
  r.metrics.push_back({"r_max_over_r_min", "", m.r_half_ratio, 1.0, kRatioTarget - 1, round});
  r.metrics.push_back({"fourfold_amplitude", "", m.fourfold_amplitude, 0.0, kAmplitudeTarget, round});
  r.metrics.push_back({"twofold_amplitude", "", m.twofold_amplitude, 0.0, kAmplitudeTarget, round});
  r.metrics.push_back({"onefold_amplitude", "", m.onefold_amplitude, 0.0, kAmplitudeTarget, round});
  Series angle{"angle per azimuth bin", "azimuth (deg)", "angle of repose (deg)", {}, {}, false};
  Series radius{"radius at half height", "azimuth (deg)", "r at H/2 (cells)", {}, {}, false};
  for (int k = 0; k < kConeAzimuthBins; ++k) {
    const double phi = (k + 0.5) * 360.0 / kConeAzimuthBins;
    if (std::isfinite(m.bin_angle_deg[std::size_t(k)])) {
      angle.x.push_back(phi);
      angle.y.push_back(m.bin_angle_deg[std::size_t(k)]);
    }
    if (std::isfinite(m.bin_r_half[std::size_t(k)])) {
      radius.x.push_back(phi);
      radius.y.push_back(m.bin_r_half[std::size_t(k)]);
    }
  }
  r.series.push_back(angle);
  r.series.push_back({"target " + target.name, "azimuth (deg)", "angle of repose (deg)", {0, 360},
                      {target.repose_deg, target.repose_deg}, true});
  r.series.push_back(radius);
  if (const AxisDiagonalAngles a = axis_diagonal_angles(m); a.ok) {
    char line[160];
    std::snprintf(line, sizeof line, "angle near the axes %.1f deg, near the diagonals %.1f deg", a.axis_deg, a.diagonal_deg);
    r.notes.push_back(line);
  }
  r.notes.push_back("pile height " + std::to_string(int(m.height_cells)) + " cells, " + std::to_string(p.poured) +
                    " grains; per-bin angle spread " + std::to_string(m.angle_spread_deg) + " deg over " +
                    std::to_string(m.bins) + " bins");
  if (!p.settled) r.notes.push_back("the pile had not come to rest after the settle limit");
  return r;
}

}  // namespace granular::accuracy
