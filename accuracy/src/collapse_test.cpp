#include <algorithm>
#include <array>
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

constexpr int kBins = 36;

/// Lube et al. 2004's normalised runout: 1.24 a below a = 1.7, 1.6 a^(1/2) above.
double lube_runout(double a) { return a < 1.7 ? 1.24 * a : 1.6 * std::sqrt(a); }

/// The deposit's radius: the mean over 36 azimuth bins of the largest column-centre distance
/// (plus half a cell, the column's outer edge) of a column holding a grain above the floor.
double deposit_radius(const Grid& g, double c, bool& touches_edge) {
  std::array<double, kBins> far{};
  const Int3 s = g.size();
  touches_edge = false;
  for (int y = 0; y < s.y; ++y)
    for (int x = 0; x < s.x; ++x) {
      bool grain = false;
      for (int z = 1; z < s.z && !grain; ++z) grain = g.at({x, y, z}) == Material::Granular;
      if (!grain) continue;
      if (x == 0 || y == 0 || x == s.x - 1 || y == s.y - 1) touches_edge = true;
      const double dx = x + 0.5 - c, dy = y + 0.5 - c;
      double phi = std::atan2(dy, dx);
      if (phi < 0) phi += 2 * std::numbers::pi;
      const int k = std::min(int(phi / (2 * std::numbers::pi) * kBins), kBins - 1);
      far[std::size_t(k)] = std::max(far[std::size_t(k)], std::hypot(dx, dy) + 0.5);
    }
  double sum = 0;
  for (double f : far) sum += f;
  return sum / kBins;
}

}  // namespace

TestReport run_collapse_test(const SuiteOptions& o) {
  const int r0 = o.quick ? 8 : 32;
  const std::vector<double> ratios{0.5, 1, 2, 4, 8};
  std::string scene = "cylinder of radius R0 = " + std::to_string(r0) +
                      " cells on a floor, height a R0 for a in {0.5, 1, 2, 4, 8}, released at once, run until at rest";
  TestReport r = open_report(o, "collapse",
                             "Column collapse: normalised runout against aspect ratio (Lube et al. 2004)", scene);
  Series runout{"measured", "aspect ratio a = H0 / R0", "(R_inf - R0) / R0", {}, {}, false};
  Series reference{"Lube et al. 2004", "aspect ratio a = H0 / R0", "(R_inf - R0) / R0", {}, {}, true};
  Series stop{"stop time", "H0 (cells)", "ticks to rest", {}, {}, false};
  for (double a = 0.25; a <= 10; a *= 1.1) {
    reference.x.push_back(a);
    reference.y.push_back(lube_runout(a));
  }
  for (double a : ratios) {
    const int h0 = int(std::lround(a * r0));
    const int half = int(std::ceil(r0 * (1 + 1.5 * lube_runout(a)))) + 8;
    const Int3 size{2 * half, 2 * half, h0 + 4};
    Grid g(size);
    g.fill(Box{{0, 0, 0}, {size.x, size.y, 1}}, Material::Solid);
    const double c = half;
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        if (std::hypot(x + 0.5 - c, y + 0.5 - c) <= r0) g.fill(Box{{x, y, 1}, {x + 1, y + 1, 1 + h0}}, Material::Granular);
    bool edge = false;
    const double r_start = deposit_radius(g, c, edge);
    World world(test_world_def(o, size), g);
    const MaterialCounts before = world.count();
    const auto start = std::chrono::steady_clock::now();
    const SettleResult rest = settle(world, 64ull * std::uint64_t(h0 + half) + 1024);
    const Grid final_grid = world.read_grid();
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.ticks += rest.ticks + 8;
    r.cell_updates += double(size.x) * size.y * size.z * double(rest.ticks + 8);
    r.conserved = r.conserved && final_grid.count() == before;
    const double r_inf = deposit_radius(final_grid, c, edge);
    const double normalised = (r_inf - r_start) / r_start;
    log_line(o, "  a = " + std::to_string(a) + ": (R_inf - R0) / R0 = " + std::to_string(normalised) + ", " +
                    std::to_string(rest.ticks) + " ticks to rest");
    runout.x.push_back(a);
    runout.y.push_back(normalised);
    stop.x.push_back(h0);
    stop.y.push_back(double(rest.ticks));
    if (edge) r.notes.push_back("a = " + std::to_string(a) + ": the deposit reached the grid's edge");
    if (!rest.settled) r.notes.push_back("a = " + std::to_string(a) + ": not at rest within the tick limit");
  }
  std::vector<double> lo_a, lo_r, hi_a, hi_r;
  for (std::size_t i = 0; i < runout.x.size(); ++i) {
    (runout.x[i] < 1.7 ? lo_a : hi_a).push_back(runout.x[i]);
    (runout.x[i] < 1.7 ? lo_r : hi_r).push_back(runout.y[i]);
  }
  const PowerFit lo = fit_power(lo_a, lo_r), hi = fit_power(hi_a, hi_r);
  const std::string lube = "Lube, Huppert, Sparks & Hallworth, J. Fluid Mech. 508, 175 (2004): (R_inf - R0)/R0 = 1.24 a (a < 1.7), 1.6 a^(1/2) (a > 1.7)";
  r.metrics.push_back({"runout_exponent_low_a", "", lo.ok ? lo.exponent : std::nan(""), 1.0, 0.1, lube});
  r.metrics.push_back({"runout_exponent_high_a", "", hi.ok ? hi.exponent : std::nan(""), 0.5, 0.1, lube});
  char line[200];
  std::snprintf(line, sizeof line, "prefactors: %.3f below a = 1.7 (Lube 1.24), %.3f above (Lube 1.6)", lo.prefactor,
                hi.prefactor);
  r.notes.push_back(line);
  r.series.push_back(runout);
  r.series.push_back(reference);
  r.series.push_back(stop);
  return r;
}

}  // namespace granular::accuracy
