#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "granular/accuracy/pour_cone.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// The cone test's scene scaled to a pile of `grains` grains: every length in proportion to the
/// radius r = (3 grains / (pi tan 33 deg))^(1/3) of a cone of that many grains at 33 deg, as the
/// cone test's own quick and full scenes nearly are (spout r / 20, drop height about one pile
/// height; the cone test: spout 2 for r = 40, 4 for r = 100).
struct SizedCone {
  std::uint64_t grains = 0;
  int floor = 0, height = 0;
  double spout = 0;
  std::int64_t per_tick = 0;
  std::uint64_t pour_ticks = 0, settle_ticks = 0;
};

SizedCone sized_cone(std::uint64_t grains) {
  const double tan33 = std::tan(33 * std::numbers::pi / 180);
  const double r = std::cbrt(3 * double(grains) / (std::numbers::pi * tan33)), h = r * tan33;
  SizedCone c;
  c.grains = grains;
  c.spout = std::max(1.0, r / 20);
  c.floor = 2 * int(std::ceil(1.3 * r)) + 8;  // room for a pile as low as 23 deg
  c.height = int(std::ceil(2 * h + 2 * c.spout)) + 8;
  // More than the spout's sphere holds: every void in it is filled each tick, as in the cone test.
  c.per_tick = std::int64_t(std::ceil(4 * std::numbers::pi / 3 * c.spout * c.spout * c.spout)) + 1;
  // A full spout delivers about 0.84 pi spout^2 grains a tick; the limit allows a quarter of that.
  c.pour_ticks = std::uint64_t(4 * double(grains) / (std::numbers::pi * c.spout * c.spout)) + 1000;
  c.settle_ticks = std::uint64_t(300 * h) + 1000;
  return c;
}

}  // namespace

TestReport run_cone_sizes_test(const SuiteOptions& o) {
  const std::vector<std::uint64_t> sizes =
      o.quick ? std::vector<std::uint64_t>{10000, 56234, 316228} : std::vector<std::uint64_t>{10000, 100000, 1000000};
  const std::vector<std::string> names{"small", "medium", "large"};
  std::string scene = "the cone test's pour scaled to piles of ";
  for (std::size_t i = 0; i < sizes.size(); ++i) scene += (i ? ", " : "") + std::to_string(sizes[i]);
  scene += " grains (floor 2.6 r + 8, height 2 h + 2 spout + 8, spout radius max(1, r / 20), r and h those of a "
           "33-degree cone of that many grains), poured until every grain is in, then settled";
  TestReport r = open_report(o, "cone_sizes",
                             "Poured cones of three sizes: one angle of repose at every size", scene);
  Series angles{"angle of repose", "grains in the pile", "angle of repose (deg)", {}, {}, false};
  const std::string ideal = "ideal: the angle of repose is the material's, the same for every pile many grains wide (" +
                            o.material.name + ", the cone test's target)";
  double lo = 0, hi = 0;
  r.conserved = true;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const SizedCone c = sized_cone(sizes[i]);
    const PourResult p = pour_cone(test_world_def(o, {c.floor, c.floor, c.height}), c.floor, c.height, c.per_tick,
                                   c.pour_ticks, c.settle_ticks, c.spout, Material::Granular, c.grains);
    const double angle = p.metrics.bins > 0 ? p.metrics.angle_deg : std::nan("");
    char line[240];
    std::snprintf(line, sizeof line,
                  "%s: %llu grains on a %d^2 floor x %d, spout radius %.2f, %llu ticks of pouring; pile height %.0f, "
                  "angle %.2f deg (spread %.2f over %d bins), r_max/r_min %.3f",
                  names[i].c_str(), static_cast<unsigned long long>(p.poured), c.floor, c.height, c.spout,
                  static_cast<unsigned long long>(p.pour_ticks), p.metrics.height_cells, angle, p.metrics.angle_spread_deg,
                  p.metrics.bins, p.metrics.r_half_ratio);
    log_line(o, std::string("  ") + line);
    r.notes.push_back(line);
    if (p.poured < c.grains)
      r.notes.push_back(names[i] + ": the spout poured " + std::to_string(p.poured) + " of " + std::to_string(c.grains) +
                        " grains within " + std::to_string(c.pour_ticks) + " ticks");
    if (!p.settled) r.notes.push_back(names[i] + ": the pile had not come to rest after the settle limit");
    r.seconds += p.seconds;
    r.ticks += p.ticks;
    r.cell_updates += double(c.floor) * c.floor * c.height * double(p.ticks);
    r.conserved = r.conserved && p.conserved;
    r.metrics.push_back({"angle_" + names[i], "deg", angle, o.material.repose_deg, 2.0, ideal});
    angles.x.push_back(double(p.poured));
    angles.y.push_back(angle);
    lo = i == 0 ? angle : std::min(lo, angle);
    hi = i == 0 ? angle : std::max(hi, angle);
  }
  r.metrics.push_back({"angle_range", "deg", hi - lo, 0.0, 2.0,
                       "ideal: one angle at every size (the suite's target: the largest and smallest within 2 deg)"});
  char trend[160];
  std::snprintf(trend, sizeof trend, "the largest pile's angle minus the smallest's: %+.2f deg",
                angles.y.back() - angles.y.front());
  r.notes.push_back(trend);
  r.series.push_back(angles);
  r.series.push_back({"target " + o.material.name, "grains in the pile", "angle of repose (deg)",
                      {angles.x.front(), angles.x.back()}, {o.material.repose_deg, o.material.repose_deg}, true});
  return r;
}

}  // namespace granular::accuracy
