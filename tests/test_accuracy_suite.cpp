#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "granular/accuracy/fit.hpp"
#include "granular/accuracy/report.hpp"
#include "granular/accuracy/suite.hpp"
#include "granular/errors.hpp"
#include "granular/rule_presets.hpp"
#include "test_support.hpp"

using namespace granular;
using namespace granular::accuracy;

namespace {

const Metric& metric(const TestReport& t, const std::string& name) {
  for (const Metric& m : t.metrics)
    if (m.name == name) return m;
  FAIL("no metric " << name << " in test " << t.test);
  return t.metrics.front();
}

SuiteOptions quick_options(const std::string& rules) {
  SuiteOptions o;
  o.rules = rules;
  o.quick = true;
  o.threads = 2;
  o.calibration = calibration_for(*make_rule_set(rules));  // as `granular accuracy` sets it per rule set
  return o;
}

}  // namespace

TEST_CASE("fits recover the laws they fit") {
  const std::vector<double> x{1, 2, 4, 8}, line_y{3, 5, 9, 17};
  const LineFit l = fit_line(x, line_y);
  CHECK(l.ok);
  CHECK(l.slope == doctest::Approx(2));
  CHECK(l.intercept == doctest::Approx(1));
  std::vector<double> power_y;
  for (double v : x) power_y.push_back(0.5 * std::pow(v, 1.5));
  const PowerFit p = fit_power(x, power_y);
  CHECK(p.exponent == doctest::Approx(1.5));
  CHECK(p.prefactor == doctest::Approx(0.5));
  const std::vector<double> d{4, 6, 8, 12, 16, 24};
  std::vector<double> w;
  for (double v : d) w.push_back(2.0 * std::pow(v - 1.5, 2.5));
  const BeverlooFit b = fit_beverloo(d, w);
  CHECK(b.ok);
  CHECK(b.k == doctest::Approx(1.5).epsilon(0.01));
  CHECK(b.exponent == doctest::Approx(2.5).epsilon(0.01));
  CHECK_FALSE(fit_line(std::vector<double>{1}, std::vector<double>{1}).ok);
}

TEST_CASE("a metric meets its target within the tolerance, and a NaN never does") {
  Metric m{"x", "", 1.04, 1.0, 0.05, "ideal"};
  CHECK(m.met());
  CHECK(m.normalized_error() == doctest::Approx(0.8));
  m.measured = 0.9;
  CHECK_FALSE(m.met());
  m.measured = std::nan("");
  CHECK_FALSE(m.met());
}

TEST_CASE("run_suite and target_material reject bad names with the valid ones") {
  const SuiteOptions o = quick_options("paper");
  test::check_has(test::error_of<InvalidArgument>([&] { run_suite(o, {"cone", "nope"}); }), {"nope", "cone", "conservation"});
  test::check_has(test::error_of<InvalidArgument>([&] { run_suite(o, {}); }), {"no test", "valid tests"});
  test::check_has(test::error_of<InvalidArgument>([] { target_material("mud"); }), {"mud", "sand", "glass"});
}

// The quick cone, tilt, fall and conservation tests on the default rule set (inertial-24-flow),
// asserting the suite's targets where the model reaches them (repose angle 33 +- 2, start and stop
// angles of the tilted bed, fall distance exponent 2 +- 0.2) and what it reaches where it does not
// (r_max/r_min; docs/ACCURACY.md shows the gaps). The paper's rules fail the footprint checks (ratio
// 1.3, 2-fold 0.033), and the one-step rules pile at 39 deg, fall at constant speed and hold a
// tilted bed to 45 deg.
TEST_CASE("accuracy suite, quick, default rules: grains conserved, hashes agree, repose angle, avalanche angles and free fall on target") {
  const std::string rules = WorldDef{}.rules;
  REQUIRE(rules == "inertial-24-flow");
  const SuiteReport r = run_suite(quick_options(rules), {"cone", "hysteresis", "fall", "conservation"});
  REQUIRE(r.tests.size() == 4);
  const TestReport& cone = r.tests[0];
  const TestReport& tilt = r.tests[1];
  const TestReport& fall = r.tests[2];
  const TestReport& conservation = r.tests[3];
  for (const TestReport* t : {&cone, &tilt})
    for (const Metric& m : t->metrics) MESSAGE(rules << " " << t->test << " " << m.name << " = " << m.measured);
  CHECK(r.conserved());
  CHECK(metric(conservation, "count_changes_random_scenes").measured == 0);
  CHECK(metric(conservation, "hash_mismatches").measured == 0);
  CHECK(metric(conservation, "tests_not_conserving").measured == 0);
  // Moving grains that roll on lower the 45-degree staircase towards dry sand's 33 degrees: the
  // quick pile measures 31.7, the full-size one 32.1 (docs/ACCURACY.md).
  const Metric& angle = metric(cone, "angle_of_repose");
  CHECK(angle.reference == 33);
  CHECK(angle.met());
  // A slope that fails avalanches down to where the moving grains stop (quick: 37.0 and 34.5).
  CHECK(metric(tilt, "theta_start").met());
  CHECK(metric(tilt, "theta_stop").met());
  CHECK(metric(tilt, "theta_start_minus_theta_stop").met());
  CHECK(metric(fall, "fall_distance_exponent").met());
  CHECK(metric(fall, "fall_time_exponent").met());
  // Measured 1.073 here, 1.030 at full size (target 1.05); the random offset order keeps the x/y
  // ellipse out (2-fold 0.007).
  const double ratio = metric(cone, "r_max_over_r_min").measured;
  CHECK(ratio >= 1.0);
  CHECK(ratio < 1.1);
  CHECK(metric(cone, "twofold_amplitude").measured < 0.01);
  CHECK(metric(cone, "onefold_amplitude").measured < 0.01);
  CHECK(metric(cone, "fourfold_amplitude").measured < 0.03);
}

// The six tests of the fluid and gravel materials, quick, on the default rules. Asserted: what the
// model meets (grains of every material conserved, sand below and gas above the liquid, the gravel
// cone's angle and the footprint checks the sand cone passes) and that each test measured
// something. Reported only (docs/ACCURACY.md, "Gaps"): the U-tube's level difference, the dam
// break's front against Ritter's, the tank's levelling time and Torricelli's exponent, which need a
// pressure the model does not have (liquid never moves up through a connected body).
TEST_CASE("accuracy suite, quick, default rules: liquid, gas and gravel against hydrostatics, Ritter, Torricelli, Archimedes") {
  const std::string rules = WorldDef{}.rules;
  const SuiteReport r = run_suite(quick_options(rules),
                                  {"gravel_cone", "communicating_vessels", "dam_break", "levelling", "torricelli", "buoyancy"});
  REQUIRE(r.tests.size() == 6);
  for (const TestReport& t : r.tests) {
    for (const Metric& m : t.metrics)
      MESSAGE(rules << " " << t.test << " " << m.name << " = " << m.measured << " (target " << m.reference << " +- "
                    << m.tolerance << ")");
    MESSAGE(t.test << ": " << t.seconds << " s, " << t.ticks << " ticks");
    for (const Metric& m : t.metrics) CHECK(std::isfinite(m.measured));
  }
  CHECK(r.conserved());
  const TestReport& gravel = r.tests[0];
  const TestReport& buoyancy = r.tests[5];
  // A levelling time lies between 0 and the run's limit, 40 L / sqrt(g h).
  const double levelling = metric(r.tests[3], "levelling_time").measured;
  CHECK(levelling >= 0);
  CHECK(levelling <= 40);
  CHECK(metric(buoyancy, "sand_over_liquid").met());
  CHECK(metric(buoyancy, "gas_under_liquid").met());
  CHECK(metric(buoyancy, "materials_not_conserved").met());
  CHECK(metric(gravel, "angle_of_repose").reference == 40);
  CHECK(metric(gravel, "angle_of_repose").met());
  CHECK(metric(gravel, "twofold_amplitude").met());
  CHECK(metric(gravel, "onefold_amplitude").met());
}

// The three tests of the size, slope and free-fall gaps, quick. Asserted: what holds by
// construction (grains conserved, every metric measured, every pile poured in full) and how each
// test reads the grid. Reported only (docs/ACCURACY.md, "Gaps"): the angles against 33 deg, the
// crater's walls and the falling block's packing. The default rules run the crater and the block
// (a second together); the cones run on the paper's rules, whose three pours take a few seconds
// where the motion model's take about 45 on 2 cores.
TEST_CASE("accuracy suite, quick: cone sizes, dug slope and falling block measure finite values and conserve grains") {
  const std::string rules = WorldDef{}.rules;
  const SuiteReport r = run_suite(quick_options(rules), {"dug_slope", "falling_block"});
  const SuiteReport cones = run_suite(quick_options("paper"), {"cone_sizes"});
  REQUIRE(r.tests.size() == 2);
  REQUIRE(cones.tests.size() == 1);
  for (const SuiteReport* s : {&r, &cones}) {
    CHECK(s->conserved());
    for (const TestReport& t : s->tests) {
      for (const Metric& m : t.metrics) {
        MESSAGE(s->config.rules << " " << t.test << " " << m.name << " = " << m.measured << " (target " << m.reference
                                << " +- " << m.tolerance << ")");
        CHECK(std::isfinite(m.measured));
      }
      MESSAGE(t.test << ": " << t.seconds << " s, " << t.ticks << " ticks");
    }
  }
  const TestReport& sizes = cones.tests[0];
  REQUIRE(sizes.series.size() == 2);
  const Series& angles = sizes.series[0];
  REQUIRE(angles.x.size() == 3);
  // Every pile holds the grains it was scaled for: 10^4, 10^4.75 and 10^5.5.
  CHECK(angles.x[0] == 10000);
  CHECK(angles.x[1] == 56234);
  CHECK(angles.x[2] == 316228);
  CHECK(metric(sizes, "angle_range").measured >= 0);
  // The crater is dug 16 deep into a bed 24 deep: its walls measure between flat and the dug
  // hemisphere's 56 deg chord.
  const double wall = metric(r.tests[0], "wall_angle").measured;
  CHECK(wall > 0);
  CHECK(wall < 57);
  // At release the block's packing fraction is 1 by definition; its ratio after the fall lies in (0, 1].
  const double packing = metric(r.tests[1], "packing_fraction_ratio").measured;
  CHECK(packing > 0);
  CHECK(packing <= 1);
}

// The heap while poured, quick, on the default rules (2 s on 2 cores). Asserted: what holds by
// construction (the emitter's grains conserved, every metric measured, the pile at rest when the run
// ends, its angle at rest the last one measured). Reported only (docs/ACCURACY.md): the angles and the time to rest against their targets.
TEST_CASE("accuracy suite, quick: the heap while poured measures its angle and its time to rest") {
  const SuiteReport r = run_suite(quick_options(WorldDef{}.rules), {"pour"});
  REQUIRE(r.tests.size() == 1);
  const TestReport& t = r.tests[0];
  CHECK(r.conserved());
  for (const Metric& m : t.metrics) {
    MESSAGE(t.test << " " << m.name << " = " << m.measured << " (target " << m.reference << " +- " << m.tolerance << ")");
    CHECK(std::isfinite(m.measured));
  }
  REQUIRE(t.series.size() == 5);
  const Series& angle = t.series[0];
  const Series& moving = t.series[4];
  REQUIRE(angle.x.size() == moving.x.size());
  REQUIRE(!moving.y.empty());
  // The run ends at rest: fewer than 0.1% of the grains move in the last sample.
  CHECK(moving.y.back() < 0.001);
  // A pile stands from the first samples on, and its angle at rest is the last sample's.
  REQUIRE(angle.y.size() > 2);
  CHECK(std::isfinite(angle.y[1]));
  CHECK(metric(t, "rest_angle").measured == angle.y.back());
  // The pour's 16 N ticks (N = 96) are all in the report's ticks.
  CHECK(t.ticks > 16u * 96u);
}
