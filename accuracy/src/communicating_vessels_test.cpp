#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// A U-tube in a grid whose sides are its walls: a solid floor at z = 0, a channel `channel` cells
/// high over the whole length, and above it two square legs of side `leg` (x in [0, leg) and
/// [leg + wall, 2 leg + wall), y in [0, leg)) parted by a solid wall `wall` cells thick. At the
/// start the channel is full of liquid and so is the left leg, `head` cells high above the
/// channel; the right leg is empty: a valve at the bottom of the right leg just opened.
struct UTube {
  int leg, wall, channel, head;
  int channel_top() const { return 1 + channel; }
  Int3 size() const { return {2 * leg + wall, leg, channel_top() + head + 4}; }
  Grid build() const {
    const Int3 s = size();
    Grid g(s);
    g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
    g.fill(Box{{leg, 0, channel_top()}, {leg + wall, s.y, s.z}}, Material::Solid);
    g.fill(Box{{0, 0, 1}, {s.x, s.y, channel_top()}}, Material::Liquid);
    g.fill(Box{{0, 0, channel_top()}, {leg, s.y, channel_top() + head}}, Material::Liquid);
    return g;
  }
  /// The liquid level of the leg starting at x = x0 above the channel: its liquid cells at
  /// z >= channel_top() over its cross-section (a mean height in cells, a partial top layer
  /// included).
  double level(const World& world, int x0) const {
    const Int3 s = size();
    const std::vector<std::uint8_t> cells = world.read_region(Box{{x0, 0, channel_top()}, {x0 + leg, s.y, s.z}});
    double n = 0;
    for (std::uint8_t c : cells) n += c == to_cell(Material::Liquid);
    return n / (double(leg) * leg);
  }
};

}  // namespace

TestReport run_communicating_vessels_test(const SuiteOptions& o) {
  const UTube tube = o.quick ? UTube{8, 8, 4, 40} : UTube{32, 32, 8, 160};
  const Int3 s = tube.size();
  const double g = o.calibration.gravity_cells();
  // The liquid column's length along the tube at rest (both legs at head / 2, the channel between
  // the legs' centres) and the period of its oscillation, 2 pi sqrt(L / (2 g)): real water levels
  // within a few periods; the run allows 20 before it is measured, unless it comes to rest sooner.
  const double column = tube.head + tube.leg + tube.wall;
  const double period = 2 * std::numbers::pi * std::sqrt(column / (2 * g));
  const std::uint64_t limit = std::max<std::uint64_t>(256, std::uint64_t(std::ceil(20 * period / 8)) * 8);
  std::string scene = "U-tube " + std::to_string(s.x) + "x" + std::to_string(s.y) + "x" + std::to_string(s.z) + ": legs of " +
                      std::to_string(tube.leg) + "^2 cells parted by a wall " + std::to_string(tube.wall) + " thick over a channel " +
                      std::to_string(tube.channel) + " high; the channel and the left leg full of liquid " +
                      std::to_string(tube.head) + " cells above the channel, the right leg empty; run until at rest or " +
                      std::to_string(limit) + " ticks (20 oscillation periods)";
  TestReport r = open_report(o, "communicating_vessels",
                             "Communicating vessels: the two legs of a U-tube level out", scene);
  const Grid initial = tube.build();
  World world(test_world_def(o, s), initial);
  const MaterialCounts before = world.count();
  const int right = tube.leg + tube.wall;
  Series left_level{"left leg", "time t sqrt(g / H0)", "level above the channel / H0", {}, {}, false};
  Series right_level{"right leg", "time t sqrt(g / H0)", "level above the channel / H0", {}, {}, false};
  Series rest_level{"both legs at rest (H0 / 2)", "time t sqrt(g / H0)", "level above the channel / H0", {}, {}, true};
  const double time_unit = std::sqrt(tube.head / g);  // ticks per unit of t sqrt(g / H0)
  auto sample = [&](std::uint64_t tick) {
    left_level.x.push_back(double(tick) / time_unit);
    left_level.y.push_back(tube.level(world, 0) / tube.head);
    right_level.x.push_back(double(tick) / time_unit);
    right_level.y.push_back(tube.level(world, right) / tube.head);
  };
  const auto start = std::chrono::steady_clock::now();
  sample(0);
  bool settled = false;
  std::uint64_t ticks = 0, previous = world.hash();
  while (ticks < limit) {
    world.step(8);
    ticks += 8;
    sample(ticks);
    const std::uint64_t h = world.hash();
    if (h == previous) {
      settled = true;
      break;
    }
    previous = h;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.ticks = ticks;
  r.cell_updates = double(initial.cell_count()) * double(ticks);
  r.conserved = world.count() == before;
  const double left = tube.level(world, 0), right_now = tube.level(world, right);
  rest_level.x = {0, left_level.x.back()};
  rest_level.y = {0.5, 0.5};
  r.metrics.push_back({"level_difference", "cells", std::abs(left - right_now), 0.0, 1.0,
                       "hydrostatics (Stevin): connected legs open to the same pressure stand at the same level "
                       "(target: within one cell)"});
  r.series.push_back(left_level);
  r.series.push_back(right_level);
  r.series.push_back(rest_level);
  char line[240];
  std::snprintf(line, sizeof line,
                "levels above the channel at the end: left %.2f, right %.2f cells (at rest both would stand at %.2f); "
                "oscillation period 2 pi sqrt(L / 2g) = %.1f ticks",
                left, right_now, 0.5 * (left + right_now), period);
  r.notes.push_back(line);
  if (!settled) r.notes.push_back("not at rest after " + std::to_string(limit) + " ticks: measured then");
  else r.notes.push_back("at rest after " + std::to_string(ticks - 8) + " ticks");
  return r;
}

}  // namespace granular::accuracy
