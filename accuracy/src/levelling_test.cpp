#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// The run's limit and the flat stretch that counts as levelled, in shallow-water times
/// L / sqrt(g h): the slowest seiche of the tank, its fundamental, has the period 2 L / sqrt(g h).
constexpr double kLimitTimes = 40, kHoldTimes = 2, kTargetTimes = 5;

/// A closed tank in a grid whose sides are its walls: a solid floor at z = 0, `length` cells along
/// x and `width` along y, and a block of liquid 4 `depth` high over its first quarter (x < length
/// / 4) and its whole width, released at tick 0: at rest the liquid stands `depth` deep over the
/// whole floor. Four cells of air over the block.
struct Tank {
  int length, width, depth;
  int block() const { return length / 4; }
  int top() const { return 1 + 4 * depth + 4; }
  Int3 size() const { return {length, width, top()}; }
  Grid build() const {
    const Int3 s = size();
    Grid g(s);
    g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
    g.fill(Box{{0, 0, 1}, {block(), s.y, 1 + 4 * depth}}, Material::Liquid);
    return g;
  }
  /// The surface height eta(x) per x: the liquid cells above the floor in the slice at x, over
  /// the tank's width (a mean column height in cells; liquid in the air counts, a void under the
  /// surface lowers it).
  std::vector<double> profile(const World& world) const {
    const Int3 s = size();
    const std::vector<std::uint8_t> cells = world.read_region(Box{{0, 0, 1}, {s.x, s.y, s.z}});
    std::vector<double> eta(std::size_t(s.x), 0.0);
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (cells[i] == to_cell(Material::Liquid)) eta[i % std::size_t(s.x)] += 1;
    for (double& e : eta) e /= s.y;
    return eta;
  }
};

/// The surface's largest distance from the level at rest: max over x of |eta(x) - depth| in cells.
double deviation(const std::vector<double>& eta, int depth) {
  double d = 0;
  for (double e : eta) d = std::max(d, std::abs(e - depth));
  return d;
}

/// Sets `series` to the surface `eta` as eta / depth against x / L (at the slices' centres).
void set_profile(Series& series, const std::vector<double>& eta, int depth) {
  series.x.clear();
  series.y.clear();
  for (std::size_t x = 0; x < eta.size(); ++x) {
    series.x.push_back((double(x) + 0.5) / double(eta.size()));
    series.y.push_back(eta[x] / depth);
  }
}

/// The levelling of one tank.
struct Levelling {
  double time = kLimitTimes;  ///< when the surface became flat for good, in L / sqrt(g h); the limit when it never did
  Series deviation;           ///< the surface's largest distance from h against time
  Series profile;             ///< the surface at the target time (or at the end of a shorter run)
  std::string note;           ///< how the run ended, for the report's notes
};

}  // namespace

TestReport run_levelling_test(const SuiteOptions& o) {
  const std::vector<int> lengths = o.quick ? std::vector<int>{64, 128} : std::vector<int>{256, 512};
  const int width = o.quick ? 8 : 32;
  const double g = o.calibration.gravity_cells();
  std::string scene = "closed tanks L long and " + std::to_string(width) + " wide, L in {";
  for (std::size_t i = 0; i < lengths.size(); ++i) scene += (i ? ", " : "") + std::to_string(lengths[i]);
  scene += "} cells: a block of liquid 4 h high over the first L / 4, h = L / 16 the depth at rest, released at tick 0; "
           "the surface eta(x) (liquid cells per slice x over the width) sampled at least 8 times per shallow-water "
           "time L / sqrt(g h); flat: every x within 1 cell of h; run until flat for 2 L / sqrt(g h) (a period of the "
           "slowest seiche), at rest, or 40 L / sqrt(g h)";
  TestReport r = open_report(o, "levelling", "Levelling: a block of liquid released at one end of a closed tank levels out", scene);
  const std::string time_label = "time t sqrt(g h) / L", deviation_label = "surface's largest distance from h: max |eta - h| (cells)";
  const std::string x_label = "position x / L", eta_label = "surface height eta / h";
  std::vector<Levelling> runs;
  for (int length : lengths) {
    const Tank tank{length, width, length / 16};
    const Int3 s = tank.size();
    const Grid initial = tank.build();
    World world(test_world_def(o, s), initial);
    const MaterialCounts before = world.count();
    const double unit = length / std::sqrt(g * tank.depth);  // ticks per shallow-water time L / sqrt(g h)
    const std::uint64_t limit = std::max<std::uint64_t>(64, std::uint64_t(std::ceil(kLimitTimes * unit / 8)) * 8);
    const double hold = kHoldTimes * unit;
    int every = 8;  // ticks between samples: at least 8 samples a shallow-water time
    while (every > 1 && every > unit / 8) every /= 2;
    const std::string name = "L = " + std::to_string(length) + ", h = " + std::to_string(tank.depth);
    Levelling run;
    run.deviation = {name, time_label, deviation_label, {}, {}, false};
    run.profile = {name, x_label, eta_label, {}, {}, false};
    auto sample = [&](std::uint64_t tick) {
      const std::vector<double> eta = tank.profile(world);
      const double d = deviation(eta, tank.depth);
      run.deviation.x.push_back(double(tick) / unit);
      run.deviation.y.push_back(d);
      if (run.profile.x.empty() && double(tick) >= kTargetTimes * unit) set_profile(run.profile, eta, tank.depth);
      return d;
    };
    const auto start = std::chrono::steady_clock::now();
    sample(0);
    std::uint64_t ticks = 0, previous = world.hash();
    double first_flat = -1, flat_since = -1;  // ticks; -1: not flat
    bool at_rest = false, held = false;
    while (ticks < limit && !at_rest && !held) {
      world.step(every);
      ticks += std::uint64_t(every);
      const bool flat = sample(ticks) <= 1.0;
      if (flat && flat_since < 0) flat_since = double(ticks);
      if (!flat) flat_since = -1;
      if (flat && first_flat < 0) first_flat = double(ticks);
      held = flat_since >= 0 && double(ticks) - flat_since >= hold;
      if (ticks % 8 == 0) {
        const std::uint64_t h = world.hash();
        at_rest = h == previous;
        previous = h;
      }
    }
    if (run.profile.x.empty()) set_profile(run.profile, tank.profile(world), tank.depth);
    char at[64];
    std::snprintf(at, sizeof at, " at t = %.1f L / sqrt(g h)", std::min(double(ticks), kTargetTimes * unit) / unit);
    run.profile.name += at;
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.ticks += ticks;
    r.cell_updates += double(initial.cell_count()) * double(ticks);
    r.conserved = r.conserved && world.count() == before;
    const bool levelled = flat_since >= 0 && (held || at_rest);
    if (levelled) run.time = flat_since / unit;
    const double last = run.deviation.y.back();
    const std::string first_text =
        first_flat >= 0 ? ", first flat at tick " + std::to_string(std::uint64_t(first_flat)) : ", never flat";
    char line[400];
    if (levelled)
      std::snprintf(line, sizeof line,
                    "%s: flat from tick %.0f, %.2f L / sqrt(g h) (L / sqrt(g h) = %.1f ticks), and still flat %s at tick %llu",
                    name.c_str(), flat_since, run.time, unit, held ? "2 L / sqrt(g h) later" : "when it came to rest",
                    static_cast<unsigned long long>(ticks));
    else if (at_rest)
      std::snprintf(line, sizeof line,
                    "%s: came to rest at tick %llu (%.2f L / sqrt(g h), L / sqrt(g h) = %.1f ticks) with the surface up to %.2f "
                    "cells from h: never flat; reported as the limit, %.0f",
                    name.c_str(), static_cast<unsigned long long>(ticks), double(ticks) / unit, unit, last, kLimitTimes);
    else
      std::snprintf(line, sizeof line,
                    "%s: not flat for 2 L / sqrt(g h) within the limit, %llu ticks = %.0f L / sqrt(g h) (L / sqrt(g h) = %.1f "
                    "ticks); the surface up to %.2f cells from h at the end%s; reported as the limit, %.0f",
                    name.c_str(), static_cast<unsigned long long>(ticks), double(ticks) / unit, unit, last,
                    first_text.c_str(), kLimitTimes);
    run.note = line;
    log_line(o, "  " + run.note);
    runs.push_back(std::move(run));
  }
  double worst = 0;
  for (const Levelling& run : runs) worst = std::max(worst, run.time);
  r.metrics.push_back({"levelling_time", "L / sqrt(g h)", worst, 0.0, kTargetTimes,
                       "shallow-water waves cross a tank of depth h at sqrt(g h) (Lamb, Hydrodynamics, long waves in a "
                       "canal): a liquid that carries pressure levels within a few crossings; target: every x of the "
                       "surface within 1 cell of the depth at rest, for a period of the slowest seiche, from at most "
                       "5 L / sqrt(g h), at both sizes (the later of the two; the limit, 40, when one never levels)"});
  for (const Levelling& run : runs) {
    r.notes.push_back(run.note);
    r.series.push_back(run.deviation);
  }
  // The reference lines span the run's limit and the largest tank's deviation at release, 3 h.
  const double released = 3.0 * (lengths.back() / 16);
  r.series.push_back({"flat: 1 cell from h", time_label, deviation_label, {0, kLimitTimes}, {1, 1}, true});
  r.series.push_back({"target: 5 L / sqrt(g h)", time_label, deviation_label, {kTargetTimes, kTargetTimes}, {0, released}, true});
  for (const Levelling& run : runs) r.series.push_back(run.profile);
  r.series.push_back({"level at rest (h)", x_label, eta_label, {0, 1}, {1, 1}, true});
  return r;
}

}  // namespace granular::accuracy
