/// @file test_entrain.cpp
/// The motion model's entrain lever (GrainMotion::entrain, preset inertial-24-entrain): a bed tilted
/// between the lever's start angle and 45 degrees stands under inertial-24 and avalanches under the
/// lever down to below its start angle; sparse stepping stays exact while it does, and the bed comes
/// to rest and sleeps. (The plain loop and the golden pins cover the lever cell for cell:
/// test_plain_step.cpp, test_golden.cpp.)

#include <doctest/doctest.h>

#include "granular/accuracy/tilted_bed.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::test_def;
using granular::test::with_sparse;

namespace {

/// The accuracy suite's tilt-test bed at its quick size.
constexpr accuracy::TiltedBed kBed{32, 12, 48, 2, 62};

WorldDef entrain_def(Int3 size, const char* rules, bool sparse) { return with_sparse(test_def(size, rules, 2, 7), sparse); }

}  // namespace

TEST_CASE("entrain: a bed tilted at 40 degrees stands under inertial-24 and avalanches under the lever") {
  const Grid bed = kBed.build(40);
  World plain(entrain_def(bed.size(), "inertial-24", true), bed);
  World lever(entrain_def(bed.size(), "inertial-24-entrain", true), bed);
  plain.step(2000);
  lever.step(2000);
  const Grid plain_grid = plain.read_grid(), lever_grid = lever.read_grid();
  const double plain_moved = accuracy::moved_fraction(bed, plain_grid);
  const double lever_moved = accuracy::moved_fraction(bed, lever_grid);
  const double built = accuracy::tilted_bed_slope_deg(bed, kBed);
  const double plain_after = accuracy::tilted_bed_slope_deg(plain_grid, kBed);
  const double lever_after = accuracy::tilted_bed_slope_deg(lever_grid, kBed);
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
  const Grid bed = kBed.build(42);
  World dense(entrain_def(bed.size(), "inertial-24-entrain", false), bed);
  World sparse(entrain_def(bed.size(), "inertial-24-entrain", true), bed);
  for (int call = 0; call < 60; ++call) {
    const int ticks = 1 + call % 5;  // odd and even calls, across cycles
    dense.step(ticks);
    sparse.step(ticks);
    REQUIRE(sparse.hash() == dense.hash());
  }
  CHECK(accuracy::moved_fraction(bed, dense.read_grid()) > 0.01);  // the lever was at work
  dense.step(3000);
  sparse.step(3000);
  CHECK(sparse.hash() == dense.hash());
  sparse.step(16);
  CHECK(sparse.activity().active_bricks == 0);  // a bed at rest under the lever costs nothing
}
