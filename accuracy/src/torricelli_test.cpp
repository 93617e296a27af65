#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "granular/accuracy/fit.hpp"
#include "granular/world.hpp"
#include "orifice_tank.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// Discharge coefficient of a sharp-edged orifice (the vena contracta): Q = C_d a sqrt(2 g h).
constexpr double kDischargeCoefficient = 0.61;

/// Liquid cells above the plate.
double liquid_in_tank(const World& world, const OrificeTank& tank) {
  const Int3 s = tank.size();
  const std::vector<std::uint8_t> cells = world.read_region(Box{{0, 0, tank.plate_top()}, s});
  return double(std::count(cells.begin(), cells.end(), to_cell(Material::Liquid)));
}

}  // namespace

TestReport run_torricelli_test(const SuiteOptions& o) {
  const OrificeTank tank = o.quick ? OrificeTank{4, 8, 64} : OrificeTank{8, 32, 192};
  const Int3 s = tank.size();
  const double g = o.calibration.gravity_cells();
  const double area = double(tank.area());
  // Heads (h: the liquid's mean height above the plate, its volume over the cross-section) at the
  // window edges, from 90% to 20% of the fill: the start's transient and the last few orifice
  // diameters (where h ~ D) are left out.
  const std::vector<double> edges{0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2};
  std::string scene = "cylindrical tank of radius " + std::to_string(tank.radius) + " filled " + std::to_string(tank.fill) +
                      " cells high with liquid, a centred orifice of diameter " + std::to_string(tank.orifice) +
                      " in its flat bottom; liquid leaving is removed 8 cells below; the rate Q in 7 windows of the head h from 90% "
                      "to 20% of the fill";
  TestReport r = open_report(o, "torricelli",
                             "Torricelli: a tank drains through a bottom orifice at a rate growing as the square root of the head", scene);
  const Grid initial = tank.build(Material::Liquid);
  World world(test_world_def(o, s), initial);
  const MaterialCounts before = world.count();
  const Box sink = tank.sink();
  const double v0 = liquid_in_tank(world, tank);
  std::vector<double> tick_of{0}, head_of{v0 / area};
  double out = 0;
  const std::uint64_t limit = 400 * std::uint64_t(s.z) + 4000;
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t ticks = 0;
  while (ticks < limit && head_of.back() > edges.back() * tank.fill) {
    world.step(1);
    ++ticks;
    out += double(world.paint(sink, Material::Void).removed[to_cell(Material::Liquid)]);
    tick_of.push_back(double(ticks));
    head_of.push_back(liquid_in_tank(world, tank) / area);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.ticks = ticks;
  r.cell_updates = double(initial.cell_count()) * double(ticks);
  const MaterialCounts after = world.count();
  r.conserved = double(after[to_cell(Material::Liquid)]) + out == double(before[to_cell(Material::Liquid)]) &&
                after[to_cell(Material::Solid)] == before[to_cell(Material::Solid)];
  // When the head fell to h, interpolated between the ticks around it.
  auto tick_at = [&](double h) {
    for (std::size_t i = 1; i < head_of.size(); ++i)
      if (head_of[i] <= h && head_of[i] < head_of[i - 1])
        return tick_of[i - 1] + (tick_of[i] - tick_of[i - 1]) * (head_of[i - 1] - h) / (head_of[i - 1] - head_of[i]);
    return -1.0;
  };
  Series rate{"Q against h", "head h (cells)", "Q (cells per tick)", {}, {}, false};
  for (std::size_t w = 0; w + 1 < edges.size(); ++w) {
    const double h0 = edges[w] * tank.fill, h1 = edges[w + 1] * tank.fill;
    const double t0 = tick_at(h0), t1 = tick_at(h1);
    if (t0 < 0 || t1 <= t0) continue;
    rate.x.push_back(0.5 * (h0 + h1));
    rate.y.push_back((h0 - h1) * area / (t1 - t0));
  }
  const PowerFit fit = fit_power(rate.x, rate.y);
  r.metrics.push_back({"head_exponent", "", fit.ok ? fit.exponent : std::nan(""), 0.5, 0.1,
                       "Torricelli (1643), Bernoulli: the jet leaves at v = sqrt(2 g h), so Q = C_d a sqrt(2 g h) ~ h^(1/2)"});
  r.series.push_back(rate);
  const double hole = std::numbers::pi * tank.orifice * tank.orifice / 4;
  Series torricelli{"C_d a sqrt(2 g h), C_d = 0.61", "head h (cells)", "Q (cells per tick)", {}, {}, true};
  for (double h : rate.x) {
    torricelli.x.push_back(h);
    torricelli.y.push_back(kDischargeCoefficient * hole * std::sqrt(2 * g * h));
  }
  r.series.push_back(torricelli);
  // The head against time: Torricelli's law drains the tank as sqrt(h) = sqrt(h0) - C t.
  Series drain{"head", "ticks", "head h (cells)", {}, {}, false};
  const std::size_t stride = std::max<std::size_t>(1, tick_of.size() / 200);
  for (std::size_t i = 0; i < tick_of.size(); i += stride) {
    drain.x.push_back(tick_of[i]);
    drain.y.push_back(head_of[i]);
  }
  r.series.push_back(drain);
  char line[300];
  if (!rate.x.empty()) {
    const double cd = rate.y.front() / (hole * std::sqrt(2 * g * rate.x.front()));
    std::snprintf(line, sizeof line,
                  "Q = %.3g cells/tick at h = %.1f, %.3g at h = %.1f; fit Q = %.3g h^%.3f (r^2 %.3f); discharge coefficient "
                  "at the highest head %.3f (sharp-edged orifice: 0.61)",
                  rate.y.front(), rate.x.front(), rate.y.back(), rate.x.back(), fit.prefactor, fit.exponent, fit.r2, cd);
    r.notes.push_back(line);
  }
  if (head_of.back() > edges.back() * tank.fill)
    r.notes.push_back("the head had not fallen to 20% of the fill after " + std::to_string(limit) + " ticks");
  return r;
}

}  // namespace granular::accuracy
