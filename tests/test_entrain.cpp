/// @file test_entrain.cpp
/// The motion model's entrain lever (GrainMotion::entrain, preset inertial-24-entrain): a bed tilted
/// between the lever's start angle and 45 degrees stands under inertial-24 and avalanches under the
/// lever down to below its start angle; sparse stepping stays exact while it does, and the bed comes
/// to rest and sleeps. (The plain loop and the golden pins cover the lever cell for cell:
/// test_plain_step.cpp, test_golden.cpp.)

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::test_def;

namespace {

constexpr int kSlope = 32, kWidth = 12, kRunout = 48, kBase = 2;

/// A walled box holding a bed of sand inclined at `deg` along x: column 1 + i is kBase + (kSlope -
/// i - 0.5) tan(deg) cells high (the accuracy suite's hysteresis bed, quick size), a void run-out.
Grid tilted_bed(double deg) {
  const double t = std::tan(deg * std::numbers::pi / 180);
  const Int3 size{kSlope + kRunout + 2, kWidth + 2, kBase + int(std::ceil(kSlope * t)) + 4};
  Grid g(size);
  g.fill(Box{{0, 0, 0}, {size.x, size.y, 1}}, Material::Solid);
  g.fill(Box{{0, 0, 0}, {1, size.y, size.z}}, Material::Solid);
  g.fill(Box{{size.x - 1, 0, 0}, {size.x, size.y, size.z}}, Material::Solid);
  g.fill(Box{{0, 0, 0}, {size.x, 1, size.z}}, Material::Solid);
  g.fill(Box{{0, size.y - 1, 0}, {size.x, size.y, size.z}}, Material::Solid);
  for (int i = 0; i < kSlope; ++i) {
    const int h = kBase + int(std::lround((kSlope - i - 0.5) * t));
    g.fill(Box{{1 + i, 1, 1}, {2 + i, size.y - 1, 1 + h}}, Material::Granular);
  }
  return g;
}

/// The fraction of the bed's grains whose cell no longer holds a grain.
double moved_fraction(const Grid& before, const Grid& after) {
  double grains = 0, moved = 0;
  for (std::size_t i = 0; i < before.cells().size(); ++i) {
    if (before.cells()[i] != to_cell(Material::Granular)) continue;
    grains += 1;
    moved += after.cells()[i] != to_cell(Material::Granular);
  }
  return moved / grains;
}

/// The bed's surface angle in degrees: the least-squares line of the mean column height (over y)
/// against x, over the columns between 20% and 80% of the highest (the suite's hysteresis measure).
double slope_deg(const Grid& g) {
  std::vector<double> h(std::size_t(g.size().x), 0);
  for (int x = 1; x < g.size().x - 1; ++x)
    for (int y = 1; y < g.size().y - 1; ++y)
      for (int z = 1; z < g.size().z; ++z) h[std::size_t(x)] += (g.at({x, y, z}) == Material::Granular) / double(kWidth);
  const double top = *std::max_element(h.begin(), h.end());
  double n = 0, sx = 0, sh = 0, sxx = 0, sxh = 0;
  for (std::size_t x = 0; x < h.size(); ++x) {
    if (h[x] < 0.2 * top || h[x] > 0.8 * top) continue;
    n += 1, sx += double(x), sh += h[x], sxx += double(x) * double(x), sxh += double(x) * h[x];
  }
  const double slope = (n * sxh - sx * sh) / (n * sxx - sx * sx);
  return std::atan(-slope) * 180 / std::numbers::pi;
}

WorldDef entrain_def(Int3 size, const char* rules, bool sparse) {
  WorldDef def = test_def(size, rules, 2, 7);
  def.sparse = sparse;
  return def;
}

}  // namespace

TEST_CASE("entrain: a bed tilted at 40 degrees stands under inertial-24 and avalanches under the lever") {
  const Grid bed = tilted_bed(40);
  World plain(entrain_def(bed.size(), "inertial-24", true), bed);
  World lever(entrain_def(bed.size(), "inertial-24-entrain", true), bed);
  plain.step(2000);
  lever.step(2000);
  const double plain_moved = moved_fraction(bed, plain.snapshot());
  const double lever_moved = moved_fraction(bed, lever.snapshot());
  const double built = slope_deg(bed), plain_after = slope_deg(plain.snapshot()), lever_after = slope_deg(lever.snapshot());
  CAPTURE(plain_moved);
  CAPTURE(lever_moved);
  CAPTURE(built);
  CAPTURE(plain_after);
  CAPTURE(lever_after);
  // Without the lever the slope below 45 degrees stands: the few grains that topple roll off alone.
  CHECK(plain_after > built - 1);
  // With it, they set the slope below them moving, and the avalanche stops near the stop angle.
  CHECK(lever_moved > 5 * plain_moved);
  CHECK(lever_after < built - 3);
  CHECK(lever_after > 30);
  CHECK(lever.count() == bed.count());
}

TEST_CASE("entrain: sparse equals dense while the avalanche runs, and the settled bed sleeps") {
  const Grid bed = tilted_bed(42);
  World dense(entrain_def(bed.size(), "inertial-24-entrain", false), bed);
  World sparse(entrain_def(bed.size(), "inertial-24-entrain", true), bed);
  for (int call = 0; call < 60; ++call) {
    const int ticks = 1 + call % 5;  // odd and even calls, across cycles
    dense.step(ticks);
    sparse.step(ticks);
    REQUIRE(sparse.hash() == dense.hash());
  }
  CHECK(moved_fraction(bed, dense.snapshot()) > 0.01);  // the lever was at work
  dense.step(3000);
  sparse.step(3000);
  CHECK(sparse.hash() == dense.hash());
  sparse.step(16);
  CHECK(sparse.activity().active_bricks == 0);  // a bed at rest under the lever costs nothing
}
