#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "granular/accuracy/fit.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// Height of the single grain in a 4 x 4 column (the z of its cell), or -1 if none.
int grain_z(const World& w) {
  const std::vector<std::uint8_t> cells = w.read_region(Box{{0, 0, 0}, w.size()});
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (cells[i] == to_cell(Material::Granular)) return int(i / 16);
  return -1;
}

}  // namespace

TestReport run_fall_test(const SuiteOptions& o, const TestReport* collapse) {
  const std::vector<int> heights = o.quick ? std::vector<int>{16, 32, 64, 128} : std::vector<int>{16, 32, 64, 128, 256};
  const Calibration& cal = o.calibration;
  const double g_cells = cal.gravity * cal.tick_s() * cal.tick_s() / cal.cell_m;  // cells per tick^2
  std::string scene = "one grain dropped in a 4x4 column onto a solid floor from H in {";
  for (std::size_t i = 0; i < heights.size(); ++i) scene += (i ? ", " : "") + std::to_string(heights[i]);
  scene += "} cells";
  TestReport r = open_report(o, "fall", "Free fall and time scales", scene);
  Series fall_time{"fall time", "drop height H (cells)", "ticks to land", {}, {}, false};
  Series fall_ref{"sqrt(2 H / g) (calibrated g)", "drop height H (cells)", "ticks to land", {}, {}, true};
  Series distance{"distance fallen (highest drop)", "ticks t", "distance fallen (cells)", {}, {}, false};
  Series distance_ref{"g t^2 / 2 (calibrated g)", "ticks t", "distance fallen (cells)", {}, {}, true};
  std::vector<double> t_all, d_all;
  const auto start = std::chrono::steady_clock::now();
  for (int h : heights) {
    const Int3 size{4, 4, h + 2};
    World world(test_world_def(o, size));
    world.paint(Box{{0, 0, 0}, {4, 4, 1}}, Material::Solid);
    world.paint(Box{{1, 1, h}, {2, 2, h + 1}}, Material::Granular);
    const MaterialCounts before = world.count();
    int t = 0, z = h;
    std::vector<double> ts, ds;
    while (z > 1 && t < 4 * h + 16) {
      world.step(1);
      ++t;
      z = grain_z(world);
      ts.push_back(t);
      ds.push_back(h - z);
    }
    r.ticks += std::uint64_t(t);
    r.cell_updates += 16.0 * (h + 2) * t;
    r.conserved = r.conserved && world.count() == before;
    fall_time.x.push_back(h);
    fall_time.y.push_back(t);
    if (h == heights.back()) {
      distance.x = ts;
      distance.y = ds;
      for (double tt : ts) {
        distance_ref.x.push_back(tt);
        distance_ref.y.push_back(0.5 * g_cells * tt * tt);
      }
    }
    // The exponent of d(t) is fitted over the flight of the highest drop, before it lands.
    if (h == heights.back())
      for (std::size_t i = 0; i < ts.size(); ++i)
        if (ds[i] > 0 && ds[i] < h - 1) {
          t_all.push_back(ts[i]);
          d_all.push_back(ds[i]);
        }
    fall_ref.x.push_back(h);
    fall_ref.y.push_back(std::sqrt(2.0 * (h - 1) / g_cells));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const PowerFit dist = fit_power(t_all, d_all), time = fit_power(fall_time.x, fall_time.y);
  const std::string galileo = "free fall under constant gravity: d = g t^2 / 2";
  r.metrics.push_back({"fall_distance_exponent", "", dist.ok ? dist.exponent : std::nan(""), 2.0, 0.2, galileo});
  r.metrics.push_back({"fall_time_exponent", "", time.ok ? time.exponent : std::nan(""), 0.5, 0.05,
                       "free fall: t = sqrt(2 H / g)"});
  r.series.push_back(distance);
  r.series.push_back(distance_ref);
  r.series.push_back(fall_time);
  r.series.push_back(fall_ref);
  if (collapse) {
    for (const Series& s : collapse->series)
      if (s.name == "stop time") {
        const PowerFit stop = fit_power(s.x, s.y);
        r.metrics.push_back({"collapse_stop_time_exponent", "", stop.ok ? stop.exponent : std::nan(""), 0.5, 0.05,
                             "Lube et al., J. Fluid Mech. 508, 175 (2004): t_inf = 3 (H0 / g)^(1/2)"});
        Series ref{"3 sqrt(H0 / g) (calibrated g)", "H0 (cells)", "ticks to rest", {}, {}, true};
        for (double h0 : s.x) {
          ref.x.push_back(h0);
          ref.y.push_back(3 * std::sqrt(h0 / g_cells));
        }
        Series measured = s;
        measured.name = "collapse stop time";
        r.series.push_back(measured);
        r.series.push_back(ref);
      }
  } else {
    r.notes.push_back("the collapse test did not run: no collapse stop-time exponent");
  }
  char line[160];
  const MotionParams motion = make_rule_set(o.rules)->motion;
  if (motion.enabled())
    std::snprintf(line, sizeof line, "calibrated g = %.4g cells/tick^2; the grain's speed is capped at %d cells/tick", g_cells,
                  motion_window(motion.max_level()));
  else
    std::snprintf(line, sizeof line, "calibrated g = %.4g cells/tick^2; the grain's speed is capped at 1 cell/tick", g_cells);
  r.notes.push_back(line);
  return r;
}

}  // namespace granular::accuracy
