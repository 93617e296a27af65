#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "granular/accuracy/fit.hpp"
#include "granular/world.hpp"
#include "orifice_tank.hpp"
#include "hourglass.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// The silo: an OrificeTank of sand filled kStartFill silo diameters high, and the fill heights
/// (grains in the silo over its cross-section) between which the flow is measured, in silo
/// diameters: Janssen's screening makes W independent of the fill above about one diameter, and
/// the window stays above two. The two diameters drained before the window let the flow become
/// steady: from a silo at rest, W through a wide orifice (16 cells and up) still grows after half
/// a diameter has drained.
struct Silo {
  static constexpr double kStartFill = 5.0, kWindowTop = 3.0, kWindowBottom = 2.0;
  static constexpr int kWindows = 5;
  OrificeTank tank;
  Silo(int orifice, int radius) : tank{orifice, radius, int(std::lround(kStartFill * 2 * radius))} {}
  int diameter() const { return 2 * tank.radius; }
};

/// One discharge: samples of (tick, grains discharged so far).
struct Discharge {
  std::vector<double> tick, out;
  double initial = 0;     ///< grains in the silo at the start
  double rate = 0;        ///< steady W (grains per tick) while the fill falls through the window
  double fill_spread = 0; ///< (max - min) / mean of W over the window's kWindows parts
  std::vector<double> window_fill, window_rate;  ///< W per part against the fill height (silo diameters) at its middle
  bool complete = false;  ///< the fill fell through the whole window within the limits
  bool conserved = true;
  double seconds = 0, cell_updates = 0;
  std::uint64_t ticks = 0;
};

Discharge discharge(const SuiteOptions& o, const Silo& silo) {
  Discharge d;
  const Int3 s = silo.tank.size();
  const Grid initial = silo.tank.build(Material::Granular);
  World world(test_world_def(o, s), initial);
  const MaterialCounts before = world.count();
  d.initial = double(before[to_cell(Material::Granular)]);
  // Grains discharged when the fill height (grains left over the columns) is `diameters` silo diameters.
  const double per_diameter = double(silo.tank.area()) * silo.diameter();
  auto out_at = [&](double diameters) { return d.initial - diameters * per_diameter; };
  const double window_lo = out_at(Silo::kWindowTop), window_hi = out_at(Silo::kWindowBottom);
  const Box sink = silo.tank.sink();
  double out = 0;
  std::uint64_t idle = 0;
  const std::uint64_t idle_limit = 4 * std::uint64_t(s.z) + 64, tick_limit = 200 * std::uint64_t(s.z) + 4000;
  const auto start = std::chrono::steady_clock::now();
  d.tick.push_back(0);
  d.out.push_back(0);
  while (d.ticks < tick_limit && out < window_hi) {
    world.step(1);
    d.ticks += 1;
    const ChangeReport removed = world.paint(sink, Material::Void);
    const double n = double(removed.removed[to_cell(Material::Granular)]);
    out += n;
    idle = n > 0 || out == 0 ? 0 : idle + 1;
    d.tick.push_back(double(d.ticks));
    d.out.push_back(out);
    if (idle >= idle_limit) break;
  }
  d.complete = out >= window_hi;
  const MaterialCounts after = world.count();
  d.conserved = double(after[to_cell(Material::Granular)]) + out == d.initial &&
                after[to_cell(Material::Solid)] == before[to_cell(Material::Solid)];
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  d.cell_updates = double(s.x) * s.y * s.z * double(d.ticks);
  // Steady rate: a line through the samples inside the window.
  std::vector<double> t, m;
  for (std::size_t i = 0; i < d.tick.size(); ++i)
    if (d.out[i] >= window_lo && d.out[i] <= window_hi) {
      t.push_back(d.tick[i]);
      m.push_back(d.out[i]);
    }
  d.rate = fit_line(t, m).slope;
  // W per part of the window, against the fill height at the part's middle.
  for (int w = 0; w < Silo::kWindows; ++w) {
    const double lo = window_lo + (window_hi - window_lo) * w / Silo::kWindows;
    const double hi = window_lo + (window_hi - window_lo) * (w + 1) / Silo::kWindows;
    const auto first = std::lower_bound(d.out.begin(), d.out.end(), lo);
    const auto last = std::lower_bound(d.out.begin(), d.out.end(), hi);
    if (first == d.out.end() || last == d.out.end() || last <= first) continue;
    const double dt = d.tick[std::size_t(last - d.out.begin())] - d.tick[std::size_t(first - d.out.begin())];
    if (dt <= 0) continue;
    d.window_rate.push_back((*last - *first) / dt);
    d.window_fill.push_back((d.initial - 0.5 * (lo + hi)) / per_diameter);
  }
  if (!d.window_rate.empty()) {
    const auto [lo, hi] = std::minmax_element(d.window_rate.begin(), d.window_rate.end());
    double mean = 0;
    for (double v : d.window_rate) mean += v;
    mean /= double(d.window_rate.size());
    d.fill_spread = (*hi - *lo) / mean;
  }
  return d;
}

}  // namespace

TestReport run_silo_test(const SuiteOptions& o) {
  const std::vector<int> orifices = o.quick ? std::vector<int>{4, 6, 8, 12} : std::vector<int>{4, 6, 8, 12, 16, 24};
  std::string scene = "flat-bottomed cylindrical silo of radius R = 1.5 D + " + std::string(o.quick ? "6" : "8") +
                      ", filled 5 silo diameters (10 R) high, centred orifice D in {";
  for (std::size_t i = 0; i < orifices.size(); ++i) scene += (i ? ", " : "") + std::to_string(orifices[i]);
  scene += "}; grains leaving are removed 8 cells below and counted; W is measured while the fill height (the grains "
           "left over the silo's cross-section) falls from 3 to 2 silo diameters";
  TestReport r = open_report(o, "silo",
                             "Silo and hourglass discharge: flow rate against orifice (Beverloo) and fill level", scene);
  r.notes.push_back("the silo is filled 5 silo diameters high and W measured from 3 to 2 diameters of fill, where "
                    "Janssen's screening holds and the flow has had two diameters of drainage to become steady");
  Series w_d{"W against D", "orifice D (cells)", "W (grains per tick)", {}, {}, false};
  std::vector<Series> fill_series;
  double worst_fill_spread = 0;
  for (int orifice : orifices) {
    const Silo silo{orifice, int(1.5 * orifice) + (o.quick ? 6 : 8)};
    const Discharge d = discharge(o, silo);
    if (!d.complete)
      r.notes.push_back("D = " + std::to_string(orifice) + ": the fill did not fall to 2 silo diameters (the flow stopped "
                        "or the tick limit passed)");
    log_line(o, "  D = " + std::to_string(orifice) + ": W = " + std::to_string(d.rate) + " grains/tick, " +
                    std::to_string(d.ticks) + " ticks");
    r.seconds += d.seconds;
    r.ticks += d.ticks;
    r.cell_updates += d.cell_updates;
    r.conserved = r.conserved && d.conserved;
    w_d.x.push_back(orifice);
    w_d.y.push_back(d.rate);
    worst_fill_spread = std::max(worst_fill_spread, d.fill_spread);
    fill_series.push_back({"D = " + std::to_string(orifice), "fill height (silo diameters)", "W / W_steady",
                           d.window_fill, {}, false});
    for (double v : d.window_rate) fill_series.back().y.push_back(d.rate > 0 ? v / d.rate : 0);
  }
  const BeverlooFit fit = fit_beverloo(w_d.x, w_d.y);
  const std::string beverloo = "Beverloo, Leniger & van de Velde, Chem. Eng. Sci. 15, 260 (1961): W = C rho_b sqrt(g) (D - k d)^(5/2)";
  r.metrics.push_back({"beverloo_exponent", "", fit.ok ? fit.exponent : std::nan(""), 2.5, 0.25, beverloo});
  {
    // Beverloo's absolute rate at the largest orifice, a cell taken as one grain diameter:
    // W = C rho_b sqrt(g) (D - k d)^(5/2) with C = 0.58, k = 1.5, in grains per tick.
    const Calibration& cal = o.calibration;
    const double d_m = (w_d.x.back() - 1.5) * cal.cell_m;
    const double kg_per_s = 0.58 * cal.bulk_density * std::sqrt(cal.gravity) * std::pow(d_m, 2.5);
    const double reference = kg_per_s * cal.tick_s() / cal.cell_kg();
    r.metrics.push_back({"rate_at_largest_D", "grains/tick", w_d.y.back(), reference, 0.1 * reference,
                         "Beverloo et al. 1961 with C = 0.58, k = 1.5 grain diameters (a cell = a grain), the calibration's rho_b, g, dt"});
  }
  r.metrics.push_back({"fill_dependence", "", worst_fill_spread, 0.0, 0.05,
                       "Beverloo et al. 1961 / Janssen screening: W does not depend on the fill height (target < 5%)"});
  r.series.push_back(w_d);
  if (fit.ok) {
    Series curve{"fit C (D - k)^n", "orifice D (cells)", "W (grains per tick)", {}, {}, true};
    Series ref{"n = 5/2 through the largest D", "orifice D (cells)", "W (grains per tick)", {}, {}, true};
    const double d_last = w_d.x.back(), w_last = w_d.y.back();
    for (double dd = w_d.x.front(); dd <= d_last + 1e-9; dd += 0.5) {
      curve.x.push_back(dd);
      curve.y.push_back(fit.prefactor * std::pow(dd - fit.k, fit.exponent));
      ref.x.push_back(dd);
      ref.y.push_back(w_last * std::pow((dd - fit.k) / (d_last - fit.k), 2.5));
    }
    r.series.push_back(curve);
    r.series.push_back(ref);
    char line[200];
    std::snprintf(line, sizeof line, "fit W = %.4g (D - %.2f)^%.3f (r^2 %.4f); W in kg/s = grains/tick x %.4g",
                  fit.prefactor, fit.k, fit.exponent, fit.r2, o.calibration.cell_kg() / o.calibration.tick_s());
    r.notes.push_back(line);
  }
  for (Series& s : fill_series) r.series.push_back(std::move(s));

  // The hourglass: flow against the fraction emptied, constant from 20% to 80% in real sand.
  const int n = o.quick ? 64 : 192;
  const HourglassDischarge hg = hourglass_discharge(o, n);
  log_line(o, "  hourglass N = " + std::to_string(n) + ": W = " + std::to_string(hg.mean_rate) + " grains/tick, " +
                  std::to_string(hg.ticks) + " ticks");
  r.scene += "; the hourglass scene at N = " + std::to_string(n);
  r.seconds += hg.seconds;
  r.ticks += hg.ticks;
  r.cell_updates += hg.cell_updates;
  r.conserved = r.conserved && hg.conserved;
  r.metrics.push_back({"hourglass_flow_spread", "", hg.drained ? hg.spread : std::nan(""), 0.0, 0.05,
                       "an hourglass flows at a constant rate while it empties (from 20% to 80% emptied)"});
  Series hourglass{"hourglass", "fraction of the upper chamber emptied", "W / W_mean (hourglass)", hg.emptied, {}, false};
  for (double v : hg.rate) hourglass.y.push_back(hg.mean_rate > 0 ? v / hg.mean_rate : 0);
  r.series.push_back(hourglass);
  if (!hg.drained) r.notes.push_back("the hourglass did not empty 80% of its upper chamber within the tick limit");
  return r;
}

}  // namespace granular::accuracy
