#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "granular/accuracy/cone_metrics.hpp"
#include "granular/accuracy/height_map.hpp"
#include "granular/errors.hpp"
#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// Dry sand's hysteresis band (the hysteresis test's references): a slope fails above theta_start and
/// an avalanche stops at theta_stop, so a heap being poured stands between the two.
constexpr double kThetaStop = 33.0, kThetaStart = 36.0, kBandTolerance = 2.0;

/// Fewer grains than this share of the pile moved since the last sample is a pile at rest.
constexpr double kRestShare = 0.001;

/// The share of `now`'s grains whose cell held no sand in `before`: the grains that moved in between
/// (a measure of every rule set, with or without motion levels).
double moved_share(const Grid& before, const Grid& now) {
  const std::uint8_t sand = to_cell(Material::Granular);
  const auto was = before.cells(), is = now.cells();
  double moved = 0;
  for (std::size_t i = 0; i < is.size(); ++i) moved += is[i] == sand && was[i] != sand ? 1 : 0;
  const double grains = double(now.count()[sand]);
  return grains > 0 ? moved / grains : 0;
}

}  // namespace

TestReport run_pour_test(const SuiteOptions& o) {
  const int n = o.quick ? 96 : 192;
  const SceneInstance scene = instantiate(load_scene(find_scene("pile")), n);
  if (scene.emitters.size() != 1) throw InvalidArgument("pour: the pile scene must have exactly one emitter");
  const Emitter& spout = scene.emitters[0];
  const Int3 size = scene.grid.size();
  const double tick_s = o.calibration.tick_s();
  // The pile stands on the layer above the floor under the spout.
  const Int3 centre{size.x / 2, size.y / 2, 0};
  int floor_z = 0;
  while (floor_z < size.z && scene.grid.at({centre.x, centre.y, floor_z}) == Material::Solid) ++floor_z;
  const int sample = 8;  // ticks between measurements
  const std::uint64_t pour_end = spout.stop;
  const std::uint64_t limit = pour_end + std::uint64_t(std::ceil(60.0 / tick_s));
  char text[512];
  std::snprintf(text, sizeof text,
                "the shipped pile scene at N = %d (%dx%dx%d): its emitter pours %lld cells of sand a tick into a "
                "sphere of radius %.1f at height %.0f for %llu ticks, then the pile is watched until fewer than %.1f%% "
                "of its grains move between two samples (at most 60 s); every %d ticks the angle (measure_cone of the "
                "sand stacked without a gap on the floor, so the stream falling above it does not count) and the "
                "share of the grains in a cell that held no sand at the last sample",
                n, size.x, size.y, size.z, static_cast<long long>(spout.rate), spout.radius, spout.center.z,
                static_cast<unsigned long long>(pour_end), 100 * kRestShare, sample);
  TestReport r = open_report(o, "pour", "Heap while poured: the pile's angle during its pour and after it", text);
  World world(test_world_def(o, size), scene.grid);
  const MaterialCounts before = world.count();
  MaterialCounts poured{};
  Series angle{"the pile's angle", "time (s)", "angle (deg)", {}, {}, false};
  Series moving{"grains moved", "time (s)", "share of the grains moved since the last sample", {}, {}, false};
  double pour_max = 0, pour_max_s = 0, rest_angle = std::nan(""), rest_s = std::nan("");
  Grid last = world.read_grid();
  const Vec3 axis{size.x / 2.0, size.y / 2.0, 0};
  const auto start = std::chrono::steady_clock::now();
  while (r.ticks < limit) {
    const MaterialCounts in = run_emitters(world, scene.emitters);
    for (std::size_t m = 0; m < in.size(); ++m) poured[m] += in[m];
    world.step(1);
    r.ticks += 1;
    if (r.ticks % sample != 0) continue;
    const double t = double(r.ticks) * tick_s;
    Grid now = world.read_grid();
    const ConeMetrics cone = measure_cone(stacked_height_map(now, floor_z, Material::Granular), axis);
    const double share = moved_share(last, now);
    last = std::move(now);
    angle.x.push_back(t);
    angle.y.push_back(cone.bins > 0 ? cone.angle_deg : std::nan(""));
    moving.x.push_back(t);
    moving.y.push_back(share);
    // The pour's second half: the heap is many grains wide and growing at a steady rate.
    if (r.ticks >= pour_end / 2 && r.ticks <= pour_end && cone.bins > 0 && cone.angle_deg > pour_max) {
      pour_max = cone.angle_deg;
      pour_max_s = t;
    }
    if (r.ticks > pour_end && share < kRestShare) {
      rest_s = double(r.ticks - pour_end) * tick_s;
      rest_angle = cone.angle_deg;
      break;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.cell_updates = double(size.x) * size.y * size.z * double(r.ticks);
  // Conserved: each material's count changes by what the emitter poured alone, which took void cells.
  MaterialCounts expected = before;
  for (std::size_t m = 0; m < expected.size(); ++m) {
    expected[m] += poured[m];
    expected[to_cell(Material::Void)] -= poured[m];
  }
  r.conserved = world.count() == expected;
  const double band_mid = 0.5 * (kThetaStop + kThetaStart), band_half = 0.5 * (kThetaStart - kThetaStop) + kBandTolerance;
  const std::string band = "dry sand's hysteresis band (the hysteresis test's references): a slope steeper than theta_start = 36 "
                           "deg fails and an avalanche stops at theta_stop = 33 deg, so ";
  r.metrics.push_back({"pour_angle_max", "deg", pour_max > 0 ? pour_max : std::nan(""), band_mid, band_half,
                       band + "a heap being poured never stands above the band (the steepest angle over the pour's "
                              "second half; the band widened by the hysteresis test's 2 deg either side)"});
  r.metrics.push_back({"rest_angle", "deg", rest_angle, band_mid, band_half,
                       band + "a heap at rest after its pour stands in the band (the band widened by 2 deg either side)"});
  r.metrics.push_back({"rest_seconds", "s", rest_s, 0.5, 0.5,
                       "a heap within its band has no slope left to fail when its pour stops: its surface flow stops within "
                       "a second of simulated time (the time until fewer than 0.1% of its grains moved between two samples)"});
  const double t_end = double(pour_end) * tick_s, t_last = angle.x.empty() ? t_end : angle.x.back();
  r.series.push_back(angle);
  r.series.push_back({"theta_start (36 deg)", "time (s)", "angle (deg)", {0, t_last}, {kThetaStart, kThetaStart}, true});
  r.series.push_back({"theta_stop (33 deg)", "time (s)", "angle (deg)", {0, t_last}, {kThetaStop, kThetaStop}, true});
  r.series.push_back({"the pour ends", "time (s)", "angle (deg)", {t_end, t_end}, {kThetaStop - 10, kThetaStart + 30}, true});
  r.series.push_back(moving);
  std::snprintf(text, sizeof text, "%.0f grains poured in %.1f s; steepest angle over the pour's second half %.1f deg at %.1f s; ",
                double(last.count()[to_cell(Material::Granular)]), t_end, pour_max, pour_max_s);
  std::string note = text;
  if (std::isnan(rest_s)) {
    note += "the pile still moved 60 s after the pour ended";
  } else {
    std::snprintf(text, sizeof text, "at rest %.2f s after the pour ended, at %.1f deg", rest_s, rest_angle);
    note += text;
  }
  r.notes.push_back(note);
  return r;
}

}  // namespace granular::accuracy
