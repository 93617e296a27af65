/// @file test_fluid_scenes.cpp
/// The shipped scenes of liquids, gases and gravel (dam_break, u_tube, reservoir, sand_into_water,
/// bubbles, gravel_and_sand) run for real: each is loaded through find_scene, as the CLI and the
/// sandbox load it, built at a small N, stepped under the default rules on the CPU backend (2
/// threads), and checked for the physical behaviour it is there to show and for exact conservation of
/// every material. The bounds come from measurements of the rules (quoted beside each); a check that
/// fails means the rules no longer do what the scene shows.

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "granular/accuracy/cone_metrics.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;

namespace {

/// A shipped scene stepped under the default rules (WorldDef's) on the CPU backend with 2 threads,
/// its emitters run before every tick as the CLI and the sandbox run them.
class SceneRun {
 public:
  SceneRun(const char* name, int n)
      : scene_(load_scene(find_scene(name))),
        instance_(instantiate(scene_, n)),
        world_(test::test_def(instance_.grid.size(), WorldDef{}.rules.c_str(), 2, WorldDef{}.seed), instance_.grid),
        start_(world_.count()) {}

  /// Steps until tick() == `tick` (no step when it is there already), recording what the emitters
  /// pour.
  void run_to(std::uint64_t tick) {
    while (world_.tick() < tick) {
      if (emitting()) {
        const MaterialCounts before = world_.count();
        run_emitters(world_, instance_.emitters);
        const MaterialCounts after = world_.count();
        for (int m = 0; m < kMaterialCount; ++m)
          poured_[std::size_t(m)] += std::int64_t(after[std::size_t(m)]) - std::int64_t(before[std::size_t(m)]);
      }
      world_.step(1);
    }
  }

  /// Steps whole 8-tick cycles until one leaves the grid unchanged (at rest) or tick() reaches
  /// `max_tick`; true when it came to rest.
  bool run_to_rest(std::uint64_t max_tick) {
    std::uint64_t previous = world_.hash();
    while (world_.tick() < max_tick) {
      run_to(world_.tick() + 8);
      const std::uint64_t h = world_.hash();
      if (h == previous && !emitting()) return true;
      previous = h;
    }
    return false;
  }

  /// Cells per material the world must hold now: the starting counts plus what the emitters poured.
  MaterialCounts expected_counts() const {
    MaterialCounts c = start_;
    for (int m = 0; m < kMaterialCount; ++m)
      c[std::size_t(m)] = std::uint64_t(std::int64_t(c[std::size_t(m)]) + poured_[std::size_t(m)]);
    return c;
  }

  /// Checks World::count against expected_counts, material by material.
  void check_conserved() const {
    const MaterialCounts now = world_.count(), expected = expected_counts();
    for (int m = 0; m < kMaterialCount; ++m) {
      CAPTURE(material_name(Material(m)));
      CHECK(now[std::size_t(m)] == expected[std::size_t(m)]);
    }
  }

  const SceneInstance& instance() const { return instance_; }
  World& world() { return world_; }
  Int3 size() const { return world_.size(); }
  int n() const { return instance_.n; }

 private:
  /// True while an emitter has ticks to come.
  bool emitting() const {
    for (const Emitter& e : instance_.emitters)
      if (world_.tick() < e.stop) return true;
    return false;
  }

  Scene scene_;
  SceneInstance instance_;
  World world_;
  MaterialCounts start_;
  std::array<std::int64_t, kMaterialCount> poured_{};  // cells the emitters added (void: removed)
};

/// The cell boundary at which a scene puts a flat face at fraction `f` of N (docs/SCENES.md, the
/// rounding rule: the nearest sixteenth of a cell, halves away from zero, then the nearest whole
/// boundary, halves up).
int face(double f, int n) { return int(std::floor(std::round(16.0 * f * n) / 16.0 + 0.5)); }

/// Cells of `m` in the slab x = `x` of `g`, divided by the slab's width in y: the mean depth of `m`
/// there, in cells.
double slab_depth(const Grid& g, int x, Material m) {
  const Int3 s = g.size();
  std::int64_t cells = 0;
  for (int z = 0; z < s.z; ++z)
    for (int y = 0; y < s.y; ++y) cells += g.at({x, y, z}) == m;
  return double(cells) / s.y;
}

/// The height of the liquid's surface over the columns x in [x0, x1): the mean over those columns
/// that hold liquid of (highest liquid layer + 1), in cells from the grid's bottom; 0 when none does.
double surface_height(const Grid& g, int x0, int x1) {
  const Int3 s = g.size();
  double sum = 0;
  int columns = 0;
  for (int y = 0; y < s.y; ++y)
    for (int x = x0; x < x1; ++x)
      for (int z = s.z - 1; z >= 0; --z)
        if (g.at({x, y, z}) == Material::Liquid) {
          sum += z + 1;
          ++columns;
          break;
        }
  return columns ? sum / columns : 0.0;
}

}  // namespace

TEST_CASE("fluid scenes: dam_break: the released column runs out along the channel and the pool finds its level") {
  // Measured at N = 32 (seeds 0..7): the front (the last slab holding >= 1 cell of water on
  // average) is at 16..20 cells at tick 50 and 21..28 at tick 100, reaches the far wall at tick
  // 250..480, and the pool's depth varies by 0.25..0.75 cells along the channel at tick 3000 (1.0..1.5
  // at tick 2000). Ritter's ideal front runs at 2 sqrt(g H0) = 11 cells per tick here (g = 2
  // cells/tick^2, H0 = 16 cells); the rules' front moves about 0.2 cells per tick. The depth first
  // varies by at most a cell at tick 1700..2025.
  const int n = 32;
  SceneRun run("dam_break", n);
  const int length = run.size().x;
  auto front = [&] {
    const Grid g = run.world().read_grid();
    int f = 0;
    for (int x = 0; x < length; ++x)
      if (slab_depth(g, x, Material::Liquid) >= 1.0) f = x + 1;
    return f;
  };
  auto depth_range = [&] {
    const Grid g = run.world().read_grid();
    double lo = 1e9, hi = 0;
    for (int x = 0; x < length; ++x) {
      const double d = slab_depth(g, x, Material::Liquid);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    return hi - lo;
  };
  // The column: 0.25 N long, 0.5 N high, on the floor at the x = 0 end.
  REQUIRE(front() == face(0.25, n));
  CHECK(slab_depth(run.world().read_grid(), 0, Material::Liquid) == doctest::Approx(0.5 * n));

  std::vector<int> fronts;
  for (std::uint64_t t : {25, 50, 100}) {
    run.run_to(t);
    fronts.push_back(front());
  }
  MESSAGE("dam_break N=32: front at ticks 25, 50, 100: " << fronts[0] << ", " << fronts[1] << ", " << fronts[2]
                                                          << " cells (column front at " << face(0.25, n) << ")");
  CHECK(fronts[0] > face(0.25, n));
  CHECK(fronts[1] > fronts[0]);
  CHECK(fronts[2] >= 0.6 * n);
  run.run_to(600);
  CHECK(front() == length);  // the surge has reached the far wall
  // Level: the depth varies by at most a cell along the channel, by tick 3000.
  double range = depth_range();
  while (range > 1.0 && run.world().tick() < 3000) {
    run.run_to(run.world().tick() + 250);
    range = depth_range();
  }
  MESSAGE("dam_break N=32: depth varies by " << range << " cells along the channel at tick " << run.world().tick()
                                             << " (mean depth "
                                             << double(run.world().count()[to_cell(Material::Liquid)]) /
                                                    (double(length) * run.size().y)
                                             << ")");
  CHECK(range <= 1.0);
  run.check_conserved();
}

namespace {

/// A scene of two open vessels joined below their surfaces (u_tube, reservoir) run at N = 32 to
/// rest: the surface heights of its two vessels at a few ticks.
struct VesselsRun {
  std::string label;                     ///< scene and vessels, for messages ("u_tube N=32, left/right")
  std::vector<std::uint64_t> ticks;      ///< when the levels were read
  std::vector<double> left, right;       ///< surface heights of the left and right vessels, in cells
  bool at_rest = false;                  ///< it came to rest before the tick limit
  bool conserved = false;                ///< World::count equals the starting counts at the end
  double target = 0;                     ///< the common level of the vessels' water, in cells
};

/// Runs the scene `name` at N = `n` to rest (at most 6000 ticks), reading the surface heights over
/// the columns x in [left_x0, left_x1) and [right_x0, right_x1) at ticks 0, 250, 1000 and at the end.
/// The target is the level at which both vessels hold the water they hold above their starting
/// surfaces' bottoms: sum of width x starting height over sum of widths, everything below both
/// surfaces (floor, passage, pipe) staying full.
VesselsRun run_vessels(const char* name, const char* vessels, int n, int left_x0, int left_x1, int right_x0,
                       int right_x1) {
  SceneRun run(name, n);
  VesselsRun r;
  r.label = std::string(name) + " N=" + std::to_string(n) + ", " + vessels;
  auto read = [&] {
    const Grid g = run.world().read_grid();
    r.ticks.push_back(run.world().tick());
    r.left.push_back(surface_height(g, left_x0, left_x1));
    r.right.push_back(surface_height(g, right_x0, right_x1));
  };
  read();
  for (std::uint64_t t : {250, 1000}) {
    run.run_to(t);
    read();
  }
  r.at_rest = run.run_to_rest(6000);
  read();
  r.conserved = run.world().count() == run.expected_counts();
  const double left_width = left_x1 - left_x0, right_width = right_x1 - right_x0;
  r.target = (left_width * r.left.front() + right_width * r.right.front()) / (left_width + right_width);
  return r;
}

/// Runs u_tube once for every test below (N = 32: legs 13 cells wide, the wall over x = 13..18).
const VesselsRun& u_tube_run() {
  static const VesselsRun result = [] {
    const int n = 32;
    return run_vessels("u_tube", "left/right", n, 0, face(0.4, n), face(0.6, n), n);
  }();
  return result;
}

/// Runs reservoir once for every test below (N = 32: the reservoir 16 cells wide, the tower over
/// x = 26..28, the pipe between z = 3 and 8).
const VesselsRun& reservoir_run() {
  static const VesselsRun result = [] {
    const int n = 32;
    return run_vessels("reservoir", "reservoir/tower", n, 0, face(0.5, n), face(0.8, n), face(0.9, n));
  }();
  return result;
}

/// The levels of `r` over time, for messages.
std::string vessels_figures(const VesselsRun& r) {
  char line[160];
  std::snprintf(line, sizeof line, " surface heights in cells (both should reach %.2f):", r.target);
  std::string s = r.label + line;
  for (std::size_t i = 0; i < r.ticks.size(); ++i) {
    std::snprintf(line, sizeof line, " tick %llu: %.2f/%.2f (difference %.2f);", (unsigned long long)r.ticks[i],
                  r.left[i], r.right[i], r.left[i] - r.right[i]);
    s += line;
  }
  return s + (r.at_rest ? " at rest" : " not at rest");
}

}  // namespace

TEST_CASE("fluid scenes: u_tube: the vessel comes to rest with its water conserved") {
  const VesselsRun& r = u_tube_run();
  MESSAGE(vessels_figures(r));
  CHECK(r.conserved);
  CHECK(r.at_rest);
  // The left leg starts at 0.9 N, the right at 0.3 N (29 and 10 cells above the grid's bottom).
  CHECK(r.left.front() == doctest::Approx(face(0.9, 32)));
  CHECK(r.right.front() == doctest::Approx(face(0.3, 32)));
  CHECK(r.target == doctest::Approx(0.6 * 32).epsilon(0.02));
}

// Known failures (docs/SCENES.md, "Shipped scenes"): the rules move a liquid only into room next to
// it (a fall, a topple, a sideways step on top of other liquid) and carry no pressure, so a vessel
// full of water is at rest however its surfaces differ; measured at N = 32: the difference stays
// 19.0 cells (29 against 10) from tick 0, at rest by tick 8. should_fail keeps the suite green while
// that holds and fails the day the levels meet: then drop the decorator.
TEST_CASE("fluid scenes: u_tube: the two levels get closer" * doctest::should_fail()) {
  const VesselsRun& r = u_tube_run();
  MESSAGE(vessels_figures(r));
  const double before = std::abs(r.left.front() - r.right.front()), after = std::abs(r.left.back() - r.right.back());
  CHECK(after <= 0.5 * before);
}

TEST_CASE("fluid scenes: u_tube: at rest, both levels stand within 1 cell of each other" * doctest::should_fail()) {
  const VesselsRun& r = u_tube_run();
  MESSAGE(vessels_figures(r));
  REQUIRE(r.at_rest);
  CHECK(std::abs(r.left.back() - r.right.back()) <= 1.0);
}

TEST_CASE("fluid scenes: reservoir: the reservoir and the tower come to rest with their water conserved") {
  const VesselsRun& r = reservoir_run();
  MESSAGE(vessels_figures(r));
  CHECK(r.conserved);
  CHECK(r.at_rest);
  // The reservoir starts at 0.85 N (27 cells above the grid's bottom), the tower's water at the
  // pipe's roof, 0.25 N (8 cells); they agree at 0.75 N (24 cells).
  CHECK(r.left.front() == doctest::Approx(face(0.85, 32)));
  CHECK(r.right.front() == doctest::Approx(face(0.25, 32)));
  CHECK(r.target == doctest::Approx(0.75 * 32).epsilon(0.02));
}

// Known failures, as u_tube's: the rules carry no pressure, so the reservoir's weight does not reach
// the tower through the full pipe and nothing lifts the tower's water; measured at N = 32: the
// reservoir stays at 27 cells and the tower at 8 (the pipe's roof), 19.0 cells apart against a
// common level of 24, the grid unchanged from tick 0 (at rest by tick 8). should_fail keeps the
// suite green while that holds and fails the day the tower fills: then drop the decorator.
TEST_CASE("fluid scenes: reservoir: the tower's water rises at least half way to the common level" *
          doctest::should_fail()) {
  const VesselsRun& r = reservoir_run();
  MESSAGE(vessels_figures(r));
  CHECK(r.right.back() - r.right.front() >= 0.5 * (r.target - r.right.front()));
}

TEST_CASE("fluid scenes: reservoir: at rest, the reservoir and the tower stand within 1 cell of each other" *
          doctest::should_fail()) {
  const VesselsRun& r = reservoir_run();
  MESSAGE(vessels_figures(r));
  REQUIRE(r.at_rest);
  CHECK(std::abs(r.left.back() - r.right.back()) <= 1.0);
}

TEST_CASE("fluid scenes: sand_into_water: the sand sinks to the tank's floor and lifts the surface by its volume") {
  // Measured at N = 32 (seeds 0, 1): 768 grains poured; their mean height 6.4..6.5 cells against a
  // surface at 15.0 (13.0 before); 133..135 of them on the tank's floor; the surface rose 1.97 cells
  // against 2.04 for the poured volume spread over the tank (0.92 against 0.92 at N = 24, 2.70 against
  // 2.80 at N = 48). 3% of the grains stand above the surface: the heap is a steep pillar under water.
  const int n = 32;
  SceneRun run("sand_into_water", n);
  const Int3 size = run.size();
  const int floor = face(0.04, n);
  const Grid start = run.world().read_grid();
  const double surface0 = surface_height(start, 0, size.x);
  std::int64_t water_columns = 0;  // the tank's area, in columns
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) water_columns += start.at({x, y, floor}) == Material::Liquid;
  REQUIRE(water_columns > 0);
  CHECK(surface0 == doctest::Approx(face(0.4, n)));

  REQUIRE(run.instance().emitters.size() == 1);
  const Emitter& emitter = run.instance().emitters[0];
  CHECK(emitter.material == Material::Granular);
  const bool rested = run.run_to_rest(emitter.stop + 1200);
  const Grid end = run.world().read_grid();
  run.check_conserved();
  const double surface = surface_height(end, 0, size.x);

  std::int64_t sand = 0, on_floor = 0, above = 0;
  double height_sum = 0;
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        if (end.at({x, y, z}) == Material::Granular) {
          ++sand;
          height_sum += z + 0.5;
          on_floor += z == floor;
          above += z + 0.5 > surface;
        }
  CHECK(sand == std::int64_t(emitter.rate) * std::int64_t(emitter.stop - emitter.start));  // the stream never clogged
  REQUIRE(sand > 0);
  const double mean_height = height_sum / double(sand);
  const double rise = surface - surface0, displaced = double(sand - above) / double(water_columns);
  MESSAGE("sand_into_water N=32 at tick " << run.world().tick() << std::string(rested ? " (at rest)" : " (still moving)") << ": "
                                          << sand << " grains, mean height " << mean_height << " under a surface at "
                                          << surface << " (was " << surface0 << "); " << on_floor << " on the floor, "
                                          << above << " above the surface; surface rise " << rise
                                          << " for a displaced volume of " << displaced);
  // The sand comes to rest under the water; the water itself rests only when its surface ends in
  // whole layers (a partly filled top layer keeps walking: docs/design/materials.md).
  auto sand_cells = [&] {
    const Grid g = run.world().read_grid();
    std::vector<std::size_t> at;
    for (std::size_t i = 0; i < g.cells().size(); ++i)
      if (g.cells()[i] == to_cell(Material::Granular)) at.push_back(i);
    return at;
  };
  const auto sand_now = sand_cells();
  run.world().step(64);
  CHECK(sand_cells() == sand_now);
  CHECK(mean_height < surface);              // on average the sand lies under the water
  CHECK(on_floor >= water_columns / 10);     // it sank through the water to the floor
  CHECK(rise == doctest::Approx(displaced).epsilon(0.25));  // Archimedes: the water rose by what the sand displaced
}

TEST_CASE("fluid scenes: bubbles: free gas rises above the water; the cup keeps its gas and catches the bubble under it") {
  // Measured at N = 32 (seeds 0..5): by tick 20 every free gas cell has left the water (z >= 30, the
  // water's highest cell at z = 18; by tick 200 all in the layer under the ceiling, z = 31); the cup's
  // 44 cells of gas grow to 76 as all 32 of the pocket under its opening rise into it (336 + 256 =
  // 592 at N = 64), and stay.
  const int n = 32;
  SceneRun run("bubbles", n);
  const Int3 size = run.size();
  // The cup: a solid cylinder of radius 0.14 N between 0.25 N and 0.45 N around (0.72, 0.25) N.
  const double cx = 0.72 * n, cy = 0.25 * n, r = 0.14 * n, inner = 0.08 * n;
  const int cup_z0 = face(0.25, n), cup_z1 = face(0.45, n);
  auto in_cup = [&](Int3 p) {
    const double dx = p.x + 0.5 - cx, dy = p.y + 0.5 - cy;
    return dx * dx + dy * dy <= r * r && p.z >= cup_z0 && p.z < cup_z1;
  };
  struct Census {
    std::int64_t cup_gas = 0, free_gas = 0, under_cup = 0;  // under_cup: gas below the cup's opening
    int free_gas_bottom = 1 << 30, water_top = -1;      // lowest free gas layer, highest water layer
    int cup_gas_bottom = 1 << 30, cup_water_top = -1;   // the same inside the cup
  };
  auto census = [&] {
    const Grid g = run.world().read_grid();
    Census c;
    for (int z = 0; z < size.z; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
          const Material m = g.at({x, y, z});
          const bool cup = in_cup({x, y, z});
          if (m == Material::Gas) {
            if (cup) {
              ++c.cup_gas;
              c.cup_gas_bottom = std::min(c.cup_gas_bottom, z);
            } else {
              ++c.free_gas;
              c.free_gas_bottom = std::min(c.free_gas_bottom, z);
              const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
              c.under_cup += z < cup_z0 && dx * dx + dy * dy <= inner * inner;
            }
          } else if (m == Material::Liquid) {
            c.water_top = std::max(c.water_top, z);
            if (cup) c.cup_water_top = std::max(c.cup_water_top, z);
          }
        }
    return c;
  };
  const Census before = census();
  REQUIRE(before.cup_gas > 0);
  REQUIRE(before.free_gas > 0);
  REQUIRE(before.under_cup > 0);
  CHECK(before.free_gas_bottom < before.water_top);  // the pockets start under water
  CHECK(before.cup_gas_bottom > before.cup_water_top);

  run.run_to(200);
  const Census after = census();
  run.check_conserved();
  MESSAGE("bubbles N=32 at tick 200: free gas " << after.free_gas << " cells, lowest at z = " << after.free_gas_bottom
                                                << " (water up to z = " << after.water_top << "); cup gas "
                                                << before.cup_gas << " -> " << after.cup_gas << " (" << before.under_cup
                                                << " cells of gas started under its opening)");
  CHECK(after.free_gas_bottom > after.water_top);   // every free bubble has left the water
  CHECK(after.cup_gas >= before.cup_gas);  // the trapped gas stayed under the cup
  CHECK(after.cup_gas >= before.cup_gas + before.under_cup);  // and caught all of the bubble below its opening
  // Held against the roof over the water: a flat interface (the layer it lies in may hold both).
  CHECK(after.cup_gas_bottom >= after.cup_water_top);
}

TEST_CASE("fluid scenes: gravel_and_sand: from the same stream the gravel heaps steeper than the sand") {
  // Two measures of each heap's angle. The equivalent cone: the cone with the heap's volume V and
  // its second moment of radius about the emitter's axis (a cone of base radius R has <r^2> = 3 R^2
  // / 10), so R = sqrt(10 <r^2> / 3) and tan(angle) = 3 V / (pi R^3); an integral over every grain,
  // steady from seed to seed. And measure_cone, the accuracy suite's angle of repose (line fits of
  // the slopes between 0.2 and 0.8 of the height), within a degree or two of it.
  // Measured at N = 64, seeds 0..7: equivalent cones sand 23.2..23.9 deg (R 20.2..20.5 cells), gravel
  // 28.6..29.1 deg (R 18.7..18.9 cells), 4.7..5.9 deg apart, gravel's 7.3..8.4% narrower;
  // measure_cone sand 26.7..29.0 deg, gravel 30.2..31.5 deg, gravel steeper by 1.2..4.6 deg. The
  // materials' targets are 33 and 40 deg (7 deg apart; at equal volume gravel's cone is then 8.2%
  // narrower).
  const int n = 64;
  SceneRun run("gravel_and_sand", n);
  const Int3 size = run.size();
  REQUIRE(run.instance().emitters.size() == 2);
  std::uint64_t stop = 0;
  for (const Emitter& e : run.instance().emitters) stop = std::max(stop, e.stop);
  const bool rested = run.run_to_rest(stop + 1500);
  CHECK(rested);
  run.check_conserved();
  const Grid end = run.world().read_grid();
  const int floor = face(0.04, n);
  constexpr double kPi = 3.14159265358979323846, kDeg = 180.0 / kPi;
  struct Heap {
    double cone_angle = 0, radius = 0;  // the equivalent cone
    double fitted_angle = 0;            // measure_cone
  };
  Heap heaps[kMaterialCount];
  for (const Emitter& e : run.instance().emitters) {
    CAPTURE(material_name(e.material));
    Grid heap(size);  // this heap's material alone, as granular (measure_cone reads granular cells)
    double volume = 0, r2 = 0;
    for (int z = 0; z < size.z; ++z)
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x)
          if (end.at({x, y, z}) == e.material) {
            heap.set({x, y, z}, Material::Granular);
            const double dx = x + 0.5 - e.center.x, dy = y + 0.5 - e.center.y;
            volume += 1;
            r2 += dx * dx + dy * dy;
          }
    CHECK(volume == double(e.rate) * double(e.stop - e.start));  // the full stream: equal volumes
    REQUIRE(volume > 0);
    Heap& h = heaps[to_cell(e.material)];
    h.radius = std::sqrt(10.0 / 3.0 * r2 / volume);
    h.cone_angle = std::atan(3.0 * volume / (kPi * h.radius * h.radius * h.radius)) * kDeg;
    const accuracy::ConeMetrics m = accuracy::measure_cone(heap, e.center, floor);
    CHECK(m.bins >= 30);  // a whole cone, measured all around
    h.fitted_angle = m.angle_deg;
  }
  const Heap& sand = heaps[to_cell(Material::Granular)];
  const Heap& gravel = heaps[to_cell(Material::Gravel)];
  MESSAGE("gravel_and_sand N=64: equivalent cones sand " << sand.cone_angle << " deg (R " << sand.radius
                                                         << " cells), gravel " << gravel.cone_angle << " deg (R "
                                                         << gravel.radius << "); measure_cone sand "
                                                         << sand.fitted_angle << " deg, gravel " << gravel.fitted_angle
                                                         << " deg");
  CHECK(gravel.cone_angle >= sand.cone_angle + 3.0);
  CHECK(gravel.radius <= 0.96 * sand.radius);
  CHECK(gravel.fitted_angle > sand.fitted_angle);
}
