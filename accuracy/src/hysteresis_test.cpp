#include <chrono>
#include <cmath>
#include <string>

#include "granular/accuracy/tilted_bed.hpp"
#include "granular/world.hpp"
#include "settle.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

TestReport run_hysteresis_test(const SuiteOptions& o) {
  const TiltedBed bed = o.quick ? TiltedBed{32, 12, 48, 2, 62} : TiltedBed{96, 32, 144, 2, 62};
  const double first_deg = 20, step_deg = o.quick ? 1.0 : 0.5, threshold = 0.01;
  const Int3 s = bed.size();
  std::string scene = "walled box " + std::to_string(s.x) + "x" + std::to_string(s.y) + "x" + std::to_string(s.z) + ", a bed " +
                      std::to_string(bed.slope_length) + " cells long inclined at theta along x, a run-out of " +
                      std::to_string(bed.runout) + "; theta from 20 deg in steps of " + std::to_string(step_deg) +
                      " deg, a fresh bed per step, " + std::to_string(4 * bed.slope_length) + " ticks each";
  TestReport r = open_report(o, "hysteresis",
                             "Hysteresis: angle of the first avalanche against the angle after it stops", scene);
  const auto start = std::chrono::steady_clock::now();
  Series moved_series{"grains moved", "bed angle theta (deg)", "fraction of grains moved", {}, {}, false};
  double theta_start = std::nan(""), theta_stop = std::nan("");
  World world(test_world_def(o, s));
  for (double deg = first_deg; deg <= bed.max_deg + 1e-9; deg += step_deg) {
    const Grid initial = bed.build(deg);
    world.load(initial);
    const MaterialCounts before = world.count();
    world.step(4 * bed.slope_length);
    r.ticks += 4 * std::uint64_t(bed.slope_length);
    r.cell_updates += double(s.x) * s.y * s.z * 4 * bed.slope_length;
    const Grid after = world.read_grid();
    r.conserved = r.conserved && after.count() == before;
    const double fraction = moved_fraction(initial, after);
    moved_series.x.push_back(deg);
    moved_series.y.push_back(fraction);
    if (fraction > threshold) {
      theta_start = deg;
      const std::uint64_t limit = 64ull * std::uint64_t(s.x + s.z);
      const SettleResult rest = settle(world, limit);
      r.ticks += rest.ticks + 8;
      r.cell_updates += double(s.x) * s.y * s.z * double(rest.ticks + 8);
      const Grid final_grid = world.read_grid();
      r.conserved = r.conserved && final_grid.count() == before;
      theta_stop = tilted_bed_slope_deg(final_grid, bed);
      if (!rest.settled) r.notes.push_back("the avalanche had not stopped after " + std::to_string(limit) + " ticks");
      break;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!std::isfinite(theta_start)) r.notes.push_back("no avalanche up to " + std::to_string(bed.max_deg) + " deg");
  const std::string jaeger = "Jaeger, Nagel & Behringer, Rev. Mod. Phys. 68, 1259 (1996): the maximum angle of stability exceeds the angle of repose by a few degrees";
  r.metrics.push_back({"theta_start_minus_theta_stop", "deg", theta_start - theta_stop, 3.0, 2.0, jaeger});
  r.metrics.push_back({"theta_stop", "deg", theta_stop, o.material.repose_deg, 2.0, o.material.name + " angle of repose"});
  r.metrics.push_back({"theta_start", "deg", theta_start, o.material.repose_deg + 3.0, 2.0,
                       o.material.name + " angle of repose + a few degrees (Jaeger, Nagel & Behringer 1996)"});
  r.series.push_back(moved_series);
  r.series.push_back({"avalanche threshold", "bed angle theta (deg)", "fraction of grains moved", {first_deg, bed.max_deg},
                      {threshold, threshold}, true});
  r.notes.push_back("theta_start " + std::to_string(theta_start) + " deg, theta_stop " + std::to_string(theta_stop) + " deg");
  return r;
}

}  // namespace granular::accuracy
