#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "granular/rule_presets.hpp"
#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// Ritter's dam-break front on a dry bed: x_f = 2 sqrt(g H0) t, in units of H0 and sqrt(H0 / g).
constexpr double kRitterSpeed = 2;

/// A dry channel in a grid whose sides are its walls (the closed end at x = 0): a solid floor at
/// z = 0 and a liquid column `head` cells high and 2 `head` long against the closed end, over the
/// channel's whole width, released at tick 0. The channel runs on 2.5 `head` + 8 cells past the
/// column, so the front travels 2 `head` before anything but the floor touches it.
struct DamBreak {
  int head, width;
  int column() const { return 2 * head; }
  Int3 size() const { return {column() + 2 * head + head / 2 + 8, width, 1 + head + 4}; }
  Grid build() const {
    const Int3 s = size();
    Grid g(s);
    g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
    g.fill(Box{{0, 0, 1}, {column(), s.y, 1 + head}}, Material::Liquid);
    return g;
  }
};

/// The front: the far face of the run of wet columns from the closed end along the floor, a column
/// x being wet when the layer on the floor (z = 1) holds liquid at x anywhere across the channel.
/// A drop ahead of the surge, separated by a dry column, is not the front.
int front(const World& world, const DamBreak& dam) {
  const Int3 s = dam.size();
  const std::vector<std::uint8_t> cells = world.read_region(Box{{0, 0, 1}, {s.x, s.y, 2}});
  for (int x = 0; x < s.x; ++x) {
    bool wet = false;
    for (int y = 0; y < s.y && !wet; ++y) wet = cells[std::size_t(x) + std::size_t(s.x) * std::size_t(y)] == to_cell(Material::Liquid);
    if (!wet) return x;
  }
  return s.x;
}

}  // namespace

TestReport run_dam_break_test(const SuiteOptions& o) {
  const std::vector<int> heads = o.quick ? std::vector<int>{16, 32} : std::vector<int>{32, 64, 128};
  const int width = o.quick ? 8 : 32;
  const double g = o.calibration.gravity_cells();
  std::string scene = "a liquid column H0 high and 2 H0 long at the closed end of a dry channel " + std::to_string(width) +
                      " cells wide, released at once, H0 in {";
  for (std::size_t i = 0; i < heads.size(); ++i) scene += (i ? ", " : "") + std::to_string(heads[i]);
  scene += "} cells; the front (the end of the wet floor) every tick over its first 2 H0 of travel";
  TestReport r = open_report(o, "dam_break", "Dam break: the front on a dry floor against Ritter's solution", scene);
  const std::string x_label = "time t sqrt(g / H0)", y_label = "front travel (x_f - x_dam) / H0";
  // Arrival times at travel 2 H0 k / 8 (k = 1..8), in units of sqrt(H0 / g), over every height.
  std::vector<double> t_all, d_all;
  double t_min = 0, t_max = 0;  // the first and last sample times over every height
  const MotionParams motion = make_rule_set(o.rules)->motion;
  const int top_speed = motion.enabled() ? motion_window(motion.max_level()) : 1;
  for (int head : heads) {
    const DamBreak dam{head, width};
    const Int3 s = dam.size();
    const Grid initial = dam.build();
    World world(test_world_def(o, s), initial);
    const MaterialCounts before = world.count();
    const double time_unit = std::sqrt(head / g);  // ticks per unit of t sqrt(g / H0)
    const std::uint64_t limit = std::uint64_t(std::ceil(16 * time_unit)) + 64;
    Series measured{"H0 = " + std::to_string(head), x_label, y_label, {0}, {0}, false};
    std::vector<double> tick_of{0}, travel_of{0};
    const auto start = std::chrono::steady_clock::now();
    std::uint64_t ticks = 0;
    while (ticks < limit && travel_of.back() < 2.0 * head) {
      world.step(1);
      ++ticks;
      tick_of.push_back(double(ticks));
      travel_of.push_back(double(std::max(0, front(world, dam) - dam.column())));
      measured.x.push_back(double(ticks) / time_unit);
      measured.y.push_back(travel_of.back() / head);
    }
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.ticks += ticks;
    r.cell_updates += double(initial.cell_count()) * double(ticks);
    r.conserved = r.conserved && world.count() == before;
    t_max = std::max(t_max, measured.x.back());
    if (measured.x.size() > 1) t_min = t_min > 0 ? std::min(t_min, measured.x[1]) : measured.x[1];
    // When the front reached travel d, interpolated between the ticks around it.
    int arrivals = 0;
    double last_arrival = std::nan("");
    for (int k = 1; k <= 8; ++k) {
      const double d = 2.0 * head * k / 8;
      for (std::size_t i = 1; i < travel_of.size(); ++i)
        if (travel_of[i] >= d && travel_of[i] > travel_of[i - 1]) {
          const double t = tick_of[i - 1] + (tick_of[i] - tick_of[i - 1]) * (d - travel_of[i - 1]) / (travel_of[i] - travel_of[i - 1]);
          t_all.push_back(t / time_unit);
          d_all.push_back(d / head);
          last_arrival = t;
          ++arrivals;
          break;
        }
    }
    char line[320];
    const double ritter_cells_per_tick = kRitterSpeed * std::sqrt(g * head);
    if (arrivals == 8)
      std::snprintf(line, sizeof line,
                    "H0 = %d: the front travelled 2 H0 in %.2f ticks, Ritter's %.2f (speed 2 sqrt(g H0) = %.2f cells/tick; "
                    "the rules' top speed %d cells/tick)",
                    head, last_arrival, 2.0 * head / ritter_cells_per_tick, ritter_cells_per_tick, top_speed);
    else
      std::snprintf(line, sizeof line,
                    "H0 = %d: the front travelled %.1f of 2 H0 = %d cells in %llu ticks (Ritter: %.2f ticks at %.2f cells/tick; "
                    "the rules' top speed %d cells/tick)",
                    head, travel_of.back(), 2 * head, static_cast<unsigned long long>(ticks), 2.0 * head / ritter_cells_per_tick,
                    ritter_cells_per_tick, top_speed);
    r.notes.push_back(line);
    log_line(o, "  " + std::string(line));
    r.series.push_back(std::move(measured));
  }
  // Ritter's x_f = 2 sqrt(g H0) t: the front speed fitted through the origin over the arrival
  // times (d = U t), in units of sqrt(g H0), against 2.
  double st = 0, sd = 0;
  for (std::size_t i = 0; i < t_all.size(); ++i) {
    st += t_all[i] * t_all[i];
    sd += t_all[i] * d_all[i];
  }
  const double ratio = st > 0 ? sd / st / kRitterSpeed : std::nan("");
  r.metrics.push_back({"front_over_ritter", "", ratio, 1.0, 0.15,
                       "Ritter, Z. Ver. Dtsch. Ing. 36, 947 (1892): on a dry bed the front runs at x_f = 2 sqrt(g H0) t "
                       "(fit x_f = U t through the front's arrival times over its first 2 H0 of travel, U / (2 sqrt(g H0)))"});
  Series ritter{"Ritter x_f = 2 sqrt(g H0) t", x_label, y_label, {t_min, t_max}, {kRitterSpeed * t_min, kRitterSpeed * t_max}, true};
  r.series.push_back(ritter);
  return r;
}

}  // namespace granular::accuracy
