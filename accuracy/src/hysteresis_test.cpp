#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "granular/accuracy/fit.hpp"
#include "granular/world.hpp"
#include "settle.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

constexpr double kDegree = std::numbers::pi / 180;

/// The inclined bed: a walled box (solid floor at z = 0, walls at x = 0, x = nx - 1, y = 0,
/// y = ny - 1), sand over x in [1, 1 + slope_length) rising towards x = 1, a void run-out beyond.
struct Bed {
  int slope_length, width, runout, base;
  double max_deg;
  Int3 size() const {
    return {slope_length + runout + 2, width + 2, base + int(std::ceil(slope_length * std::tan(max_deg * kDegree))) + 4};
  }
  Grid build(double deg) const {
    const Int3 s = size();
    Grid g(s);
    g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
    g.fill(Box{{0, 0, 0}, {1, s.y, s.z}}, Material::Solid);
    g.fill(Box{{s.x - 1, 0, 0}, {s.x, s.y, s.z}}, Material::Solid);
    g.fill(Box{{0, 0, 0}, {s.x, 1, s.z}}, Material::Solid);
    g.fill(Box{{0, s.y - 1, 0}, {s.x, s.y, s.z}}, Material::Solid);
    const double t = std::tan(deg * kDegree);
    for (int i = 0; i < slope_length; ++i) {
      const int h = base + int(std::lround((slope_length - i - 0.5) * t));
      g.fill(Box{{1 + i, 1, 1}, {2 + i, s.y - 1, 1 + h}}, Material::Granular);
    }
    return g;
  }
};

/// The bed's mean column height (grains per column over y) at each x of the slope.
std::vector<double> mean_heights(const Grid& g, const Bed& bed) {
  std::vector<double> h(std::size_t(g.size().x), 0);
  for (int x = 0; x < g.size().x; ++x) {
    double sum = 0;
    for (int y = 1; y <= bed.width; ++y)
      for (int z = 1; z < g.size().z; ++z) sum += g.at({x, y, z}) == Material::Granular;
    h[std::size_t(x)] = sum / bed.width;
  }
  return h;
}

/// The surface slope angle: a line fit of the mean column height against x over the columns
/// between 20% and 80% of the highest.
double slope_deg(const std::vector<double>& h) {
  double top = 0;
  for (double v : h) top = std::max(top, v);
  std::vector<double> xs, hs;
  for (std::size_t x = 0; x < h.size(); ++x)
    if (h[x] >= 0.2 * top && h[x] <= 0.8 * top) {
      xs.push_back(double(x));
      hs.push_back(h[x]);
    }
  const LineFit f = fit_line(xs, hs);
  return f.ok ? std::atan(-f.slope) / kDegree : std::nan("");
}

std::uint64_t grains_moved(const Grid& before, const Grid& after) {
  std::uint64_t moved = 0;
  const auto& a = before.cells();
  const auto& b = after.cells();
  for (std::size_t i = 0; i < a.size(); ++i)
    moved += a[i] == to_cell(Material::Granular) && b[i] != to_cell(Material::Granular);
  return moved;
}

}  // namespace

TestReport run_hysteresis_test(const SuiteOptions& o) {
  const Bed bed = o.quick ? Bed{32, 12, 48, 2, 62} : Bed{96, 32, 144, 2, 62};
  const double first_deg = 20, step_deg = o.quick ? 1.0 : 0.5, threshold = 0.01;
  TestReport r;
  r.test = "hysteresis";
  r.title = "Hysteresis: angle of the first avalanche against the angle after it stops";
  const Int3 s = bed.size();
  r.scene = "walled box " + std::to_string(s.x) + "x" + std::to_string(s.y) + "x" + std::to_string(s.z) + ", a bed " +
            std::to_string(bed.slope_length) + " cells long inclined at theta along x, a run-out of " +
            std::to_string(bed.runout) + "; theta from 20 deg in steps of " + std::to_string(step_deg) +
            " deg, a fresh bed per step, " + std::to_string(4 * bed.slope_length) + " ticks each";
  log_line(o, "hysteresis: " + r.scene);
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
    const Grid after = world.snapshot();
    r.conserved = r.conserved && after.count() == before;
    const double fraction = double(grains_moved(initial, after)) / double(before[to_cell(Material::Granular)]);
    moved_series.x.push_back(deg);
    moved_series.y.push_back(fraction);
    if (fraction > threshold) {
      theta_start = deg;
      const std::uint64_t limit = 64ull * std::uint64_t(s.x + s.z);
      const SettleResult rest = settle(world, limit);
      r.ticks += rest.ticks + 8;
      r.cell_updates += double(s.x) * s.y * s.z * double(rest.ticks + 8);
      const Grid final_grid = world.snapshot();
      r.conserved = r.conserved && final_grid.count() == before;
      theta_stop = slope_deg(mean_heights(final_grid, bed));
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
