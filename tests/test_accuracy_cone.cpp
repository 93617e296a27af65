#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "granular/accuracy/cone_metrics.hpp"
#include "granular/accuracy/height_map.hpp"
#include "granular/accuracy/pour_cone.hpp"
#include "test_support.hpp"

using namespace granular;
using namespace granular::accuracy;

namespace {

/// A grid of n x n x (height + 2) cells with a Solid floor at z = 0 and, on it, h(dx, dy) Granular
/// cells per column, where (dx, dy) is the column centre's offset from the grid's centre.
Grid paint_pile(int n, int height, const std::function<double(double, double)>& h) {
  Grid g({n, n, height + 2});
  g.fill(Box{{0, 0, 0}, {n, n, 1}}, Material::Solid);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const long cells = std::lround(std::clamp(h(x + 0.5 - n / 2.0, y + 0.5 - n / 2.0), 0.0, double(height)));
      g.fill(Box{{x, y, 1}, {x + 1, y + 1, 1 + int(cells)}}, Material::Granular);
    }
  return g;
}

/// A round cone of height `height` whose flanks rise at `degrees`.
Grid paint_cone(int n, int height, double degrees) {
  const double t = std::tan(degrees * std::numbers::pi / 180);
  return paint_pile(n, height, [&](double dx, double dy) { return height - std::hypot(dx, dy) * t; });
}

void report(const std::string& what, const ConeMetrics& m) {
  MESSAGE(what << ": H " << m.height_cells << ", angle " << m.angle_deg << " +- " << m.angle_spread_deg
                << " deg over " << m.bins << " bins, r_half " << m.r_half_min << ".." << m.r_half_max
                << " (ratio " << m.r_half_ratio << "), 4-fold " << m.fourfold_amplitude);
}

}  // namespace

TEST_CASE("measure_cone: synthetic round cones give their slope and a round footprint") {
  struct Case {
    double degrees;
    int height;
  };
  for (const Case c : {Case{30, 30}, Case{45, 40}}) {
    CAPTURE(c.degrees);
    const int n = 128;
    const ConeMetrics m = measure_cone(paint_cone(n, c.height, c.degrees), {n / 2.0, n / 2.0, 0}, 1);
    report(c.degrees == 30 ? "cone 30" : "cone 45", m);
    CHECK(std::abs(m.height_cells - c.height) <= 1);  // the apex column is rounded
    CHECK(m.bins == kConeAzimuthBins);
    CHECK(std::abs(m.angle_deg - c.degrees) < 1.5);
    CHECK(m.r_half_ratio >= 1.0);
    CHECK(m.r_half_ratio <= 1.1);
    CHECK(m.fourfold_amplitude < 0.05);
  }
}

TEST_CASE("measure_cone: a synthetic square pyramid has a square footprint") {
  const int n = 128, height = 40;
  const Grid g = paint_pile(n, height, [&](double dx, double dy) {
    return height - std::max(std::abs(dx), std::abs(dy));
  });
  const ConeMetrics m = measure_cone(g, {n / 2.0, n / 2.0, 0}, 1);
  report("square pyramid", m);
  CHECK(m.r_half_ratio > 1.25);
  CHECK(m.fourfold_amplitude > 0.05);
}

TEST_CASE("measure_cone: a crater's depth map is the cone of its walls") {
  // A bed 20 high whose crater's walls rise at 33 degrees from a flat bottom 12 deep (radius 6)
  // to the bed's level: the depth map (bed level minus height) is a truncated cone of 33 degrees.
  const int n = 96, level = 20, depth = 12;
  const double t = std::tan(33 * std::numbers::pi / 180), bottom = 6;
  const Grid bed = paint_pile(n, level, [&](double dx, double dy) {
    return level - std::clamp(depth - (std::hypot(dx, dy) - bottom) * t, 0.0, double(depth));
  });
  HeightMap d = height_map(bed, 1, Material::Granular);
  for (double& v : d.h) v = level - v;
  const ConeMetrics m = measure_cone(d, {n / 2.0, n / 2.0, 0});
  report("crater 33", m);
  CHECK(m.height_cells == depth);
  CHECK(m.bins == kConeAzimuthBins);
  CHECK(std::abs(m.angle_deg - 33) < 1.5);
  CHECK(m.r_half_ratio <= 1.1);
}

TEST_CASE("measure_cone: an empty grid measures as zeros") {
  Grid g({16, 16, 8});
  g.fill(Box{{0, 0, 0}, {16, 16, 1}}, Material::Solid);
  const ConeMetrics m = measure_cone(g, {8, 8, 0}, 1);
  CHECK(m.height_cells == 0);
  CHECK(m.bins == 0);
  CHECK(m.r_half_ratio == 0);
}

namespace {

/// The poured cone of the two rule-set tests: 96 x 96 x 64, 60 grains per tick offered for 4000
/// ticks (the radius-2 spout takes about 7.5 per tick: some 30,000 grains, a pile 25 cells high).
PourResult pour_small(const char* rules) {
  return pour_cone(test::test_def({96, 96, 64}, rules), 96, 64, 60, 4000, 4000);
}

void check_conserved(const PourResult& r) {
  CHECK(r.poured > 0);
  CHECK(r.before[to_cell(Material::Granular)] == 0);
  CHECK(r.after[to_cell(Material::Granular)] == r.poured);
  CHECK(r.after[to_cell(Material::Solid)] == r.before[to_cell(Material::Solid)]);
  CHECK(r.conserved);
  CHECK(r.settled);
}

}  // namespace

// The azimuth-mean angle of a pile whose columns step down one cell per cell along both the axes
// and the diagonals lies between atan(1/sqrt 2) = 35.3 degrees (diagonals) and 45 (axes): the
// synthetic square pyramid measures 41.7. The poured piles measure about 38 (about 43 along the
// axes, 35 along the diagonals), so the bound checked is that range, not 45 +- 3.
TEST_CASE("pour_cone: a grain budget stops the pour at that many grains") {
  const PourResult r = pour_cone(test::test_def({32, 32, 32}, "paper"), 32, 32, 60, 4000, 2000, 2.0, Material::Granular, 500);
  CHECK(r.poured == 500);
  CHECK(r.pour_ticks < 4000);
  check_conserved(r);
}

TEST_CASE("pour_cone: paper and isotropic rules conserve grains; paper's footprint is the less round") {
  auto pour_checked = [](const char* rules) {
    const PourResult r = pour_small(rules);
    report(rules, r.metrics);
    MESSAGE(rules << ": " << r.poured << " grains, " << r.ticks << " ticks, " << r.seconds << " s");
    check_conserved(r);
    CHECK(r.metrics.angle_deg > 34);
    CHECK(r.metrics.angle_deg < 46);
    return r;
  };
  const PourResult paper = pour_checked("paper");
  CHECK(paper.metrics.r_half_ratio > 1.2);
  const PourResult iso = pour_checked("isotropic");
  CHECK(iso.metrics.r_half_ratio < paper.metrics.r_half_ratio);
}

TEST_CASE("stacked_height_map: a column's height stops at its first gap, height_map counts every grain") {
  Grid g({4, 4, 16});
  g.fill(Box{{0, 0, 0}, {4, 4, 1}}, Material::Solid);
  g.fill(Box{{1, 1, 1}, {2, 2, 6}}, Material::Granular);  // a stack of 5 on the floor
  g.fill(Box{{1, 1, 9}, {2, 2, 12}}, Material::Granular); // 3 more falling above a gap
  g.set({2, 2, 4}, Material::Granular);                   // a grain in the air over an empty column
  const HeightMap stacked = stacked_height_map(g, 1, Material::Granular);
  const HeightMap all = height_map(g, 1, Material::Granular);
  CHECK(stacked.at(1, 1) == 5);
  CHECK(all.at(1, 1) == 8);
  CHECK(stacked.at(2, 2) == 0);
  CHECK(all.at(2, 2) == 1);
  CHECK(stacked.at(0, 0) == 0);
}
