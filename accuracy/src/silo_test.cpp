#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "granular/accuracy/fit.hpp"
#include "granular/world.hpp"
#include "hourglass.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// A cylindrical silo: a sink of kSink layers at the bottom (all but its top 2 cleared every tick, so
/// a grain is counted once it has fallen clear of the plate, however fast it falls), a solid
/// plate 2 cells thick with a centred round orifice of diameter `orifice`, a solid shell outside
/// radius `radius`, and sand filled to `fill` layers above the plate.
struct Silo {
  int orifice, radius, fill;
  static constexpr int kSink = 8, kPlate = 2;
  int plate_top() const { return kSink + kPlate; }
  Int3 size() const { return {2 * radius + 4, 2 * radius + 4, plate_top() + fill + 4}; }
  Grid build() const {
    const Int3 s = size();
    Grid g(s);
    const double c = s.x / 2.0;
    for (int y = 0; y < s.y; ++y)
      for (int x = 0; x < s.x; ++x) {
        const double r = std::hypot(x + 0.5 - c, y + 0.5 - c);
        const bool in_hole = r <= orifice / 2.0;
        if (r > radius) g.fill(Box{{x, y, kSink}, {x + 1, y + 1, s.z}}, Material::Solid);
        else if (!in_hole) g.fill(Box{{x, y, kSink}, {x + 1, y + 1, plate_top()}}, Material::Solid);
        if (r <= radius) g.fill(Box{{x, y, plate_top()}, {x + 1, y + 1, plate_top() + fill}}, Material::Granular);
      }
    return g;
  }
};

/// One discharge: samples of (tick, grains discharged so far).
struct Discharge {
  std::vector<double> tick, out;
  double initial = 0;     ///< grains in the silo at the start
  double rate = 0;        ///< steady W (grains per tick) between 20% and 80% of the total discharged
  double fill_spread = 0; ///< (max - min) / mean of W over the 10%-windows between 20% and 80%
  std::vector<double> window_fill, window_rate;  ///< W per 10% window against the fill level (fraction of the start)
  bool conserved = true;
  double seconds = 0, cell_updates = 0;
  std::uint64_t ticks = 0;
};

Discharge discharge(const SuiteOptions& o, const Silo& silo) {
  Discharge d;
  const Int3 s = silo.size();
  const Grid initial = silo.build();
  World world(test_world_def(o, s), initial);
  const MaterialCounts before = world.count();
  d.initial = double(before[to_cell(Material::Granular)]);
  const Box sink{{0, 0, 0}, {s.x, s.y, Silo::kSink - 2}};
  double out = 0;
  std::uint64_t idle = 0;
  const std::uint64_t idle_limit = 4 * std::uint64_t(s.z) + 64, tick_limit = 200 * std::uint64_t(s.z) + 4000;
  const auto start = std::chrono::steady_clock::now();
  d.tick.push_back(0);
  d.out.push_back(0);
  while (d.ticks < tick_limit) {
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
  const MaterialCounts after = world.count();
  d.conserved = double(after[to_cell(Material::Granular)]) + out == d.initial &&
                after[to_cell(Material::Solid)] == before[to_cell(Material::Solid)];
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  d.cell_updates = double(s.x) * s.y * s.z * double(d.ticks);
  // Steady rate: a line through the samples between 20% and 80% of the total.
  std::vector<double> t, m;
  for (std::size_t i = 0; i < d.tick.size(); ++i)
    if (d.out[i] >= 0.2 * out && d.out[i] <= 0.8 * out) {
      t.push_back(d.tick[i]);
      m.push_back(d.out[i]);
    }
  d.rate = fit_line(t, m).slope;
  // W per 10% window, against the fill left at the window's middle.
  for (int w = 2; w < 8; ++w) {
    const double lo = 0.1 * w * out, hi = 0.1 * (w + 1) * out;
    const auto first = std::lower_bound(d.out.begin(), d.out.end(), lo);
    const auto last = std::lower_bound(d.out.begin(), d.out.end(), hi);
    if (first == d.out.end() || last == d.out.end() || last <= first) continue;
    const double dt = d.tick[std::size_t(last - d.out.begin())] - d.tick[std::size_t(first - d.out.begin())];
    if (dt <= 0) continue;
    d.window_rate.push_back((*last - *first) / dt);
    d.window_fill.push_back((d.initial - 0.5 * (lo + hi)) / d.initial);
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
  TestReport r;
  r.test = "silo";
  r.title = "Silo and hourglass discharge: flow rate against orifice (Beverloo) and fill level";
  r.scene = "flat-bottomed cylindrical silo of radius 1.5 D + " + std::string(o.quick ? "6" : "8") +
            ", filled 2 R + " + (o.quick ? "8" : "16") + " high, centred orifice D in {";
  for (std::size_t i = 0; i < orifices.size(); ++i) r.scene += (i ? ", " : "") + std::to_string(orifices[i]);
  r.scene += "}; grains leaving are removed 8 cells below and counted";
  log_line(o, "silo: " + r.scene);
  Series w_d{"W against D", "orifice D (cells)", "W (grains per tick)", {}, {}, false};
  std::vector<Series> fill_series;
  double worst_fill_spread = 0;
  for (int orifice : orifices) {
    const int radius = int(1.5 * orifice) + (o.quick ? 6 : 8);
    const Silo silo{orifice, radius, 2 * radius + (o.quick ? 8 : 16)};
    const Discharge d = discharge(o, silo);
    log_line(o, "  D = " + std::to_string(orifice) + ": W = " + std::to_string(d.rate) + " grains/tick, " +
                    std::to_string(d.ticks) + " ticks");
    r.seconds += d.seconds;
    r.ticks += d.ticks;
    r.cell_updates += d.cell_updates;
    r.conserved = r.conserved && d.conserved;
    w_d.x.push_back(orifice);
    w_d.y.push_back(d.rate);
    worst_fill_spread = std::max(worst_fill_spread, d.fill_spread);
    fill_series.push_back({"D = " + std::to_string(orifice), "fill left (fraction of the start)",
                           "W / W_steady", d.window_fill, {}, false});
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
