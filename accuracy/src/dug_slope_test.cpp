#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "granular/accuracy/cone_metrics.hpp"
#include "granular/accuracy/height_map.hpp"
#include "granular/world.hpp"
#include "settle.hpp"
#include "suite_tests.hpp"

namespace granular::accuracy {

namespace {

/// A bed of sand filling a box `2 half` cells square to `depth` layers (the grid's sides and floor
/// are its walls, 4 void layers above), and the hemisphere of radius `radius` centred on its
/// surface at the middle that World::dig removes.
struct DugBed {
  int half, depth, radius;
  Int3 size() const { return {2 * half, 2 * half, depth + 4}; }
  Sphere crater() const { return {{double(half), double(half), double(depth)}, double(radius)}; }
};

/// The crater as a cone: the depth below the bed's level, depth - h(x, y), of every column.
HeightMap depth_map(const Grid& grid, int level) {
  HeightMap m = height_map(grid, 0, Material::Granular);
  for (double& v : m.h) v = level - v;
  return m;
}

/// The surface's mean height against the distance from the crater's axis, in 1-cell rings out to
/// the box's half width, both measured from the wall's point at half the crater's depth (ring
/// r_mid, height h_mid): walls of the same slope lie on one line through the origin.
Series profile(const std::string& name, const HeightMap& h, double c, double r_mid, double h_mid, bool reference) {
  const std::size_t rings = std::size_t(c);
  std::vector<double> sum(rings, 0), n(rings, 0);
  for (int y = 0; y < h.ny; ++y)
    for (int x = 0; x < h.nx; ++x) {
      const std::size_t k = std::size_t(std::hypot(x + 0.5 - c, y + 0.5 - c));
      if (k >= rings) continue;
      sum[k] += h.at(x, y);
      n[k] += 1;
    }
  Series s{name, "distance from the wall at half depth (cells)", "height above the wall at half depth (cells)", {}, {},
           reference};
  for (std::size_t k = 0; k < rings; ++k)
    if (n[k] > 0) {
      s.x.push_back(double(k) + 0.5 - r_mid);
      s.y.push_back(sum[k] / n[k] - h_mid);
    }
  return s;
}

/// Mean of the finite per-bin values (NaN when there is none).
double finite_mean(const std::array<double, kConeAzimuthBins>& v) {
  double sum = 0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) {
      sum += x;
      ++n;
    }
  return n ? sum / n : std::nan("");
}

}  // namespace

TestReport run_dug_slope_test(const SuiteOptions& o) {
  const DugBed bed = o.quick ? DugBed{40, 24, 16} : DugBed{104, 56, 48};
  const Int3 s = bed.size();
  std::string scene = "a bed of sand " + std::to_string(s.x) + "^2 x " + std::to_string(bed.depth) +
                      " cells (the box's walls hold it), settled; a hemisphere of radius " + std::to_string(bed.radius) +
                      " centred on its surface dug out (World::dig), then settled again; the walls' angle is measure_cone's on the "
                      "crater's depth map (bed level minus column height): per 10-degree azimuth bin, the least-squares line of the "
                      "depth against the distance from the axis over the columns between 20% and 80% of the crater's depth, "
                      "averaged over the bins";
  TestReport r = open_report(o, "dug_slope",
                             "Dug crater: the walls of a crater dug into a settled bed relax to the angle of repose", scene);
  World world(test_world_def(o, s));
  world.paint(Box{{0, 0, 0}, {s.x, s.y, bed.depth}}, Material::Granular);
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t limit = 64 * std::uint64_t(s.x + s.z) + 1024;
  const SettleResult bed_rest = settle(world, limit);
  const MaterialCounts before = world.count();
  const ChangeReport dug = world.dig(bed.crater());
  const Grid as_dug = world.read_grid();
  const SettleResult rest = settle(world, limit);
  const Grid settled = world.read_grid();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.ticks = world.tick();
  r.cell_updates = double(s.x) * s.y * s.z * double(r.ticks);
  const MaterialCounts after = settled.count();
  const std::uint64_t removed = dug.removed[to_cell(Material::Granular)];
  r.conserved = true;
  for (int m = 0; m < kMaterialCount; ++m)
    r.conserved = r.conserved && after[std::size_t(m)] == before[std::size_t(m)] -
                                                               (m == to_cell(Material::Granular) ? removed : 0) +
                                                               (m == to_cell(Material::Void) ? removed : 0);

  const Vec3 axis{double(bed.half), double(bed.half), 0};
  const ConeMetrics dug_cone = measure_cone(depth_map(as_dug, bed.depth), axis);
  const ConeMetrics wall = measure_cone(depth_map(settled, bed.depth), axis);
  const double angle = wall.bins > 0 ? wall.angle_deg : std::nan("");
  r.metrics.push_back({"wall_angle", "deg", angle, o.material.repose_deg, 2.0,
                       o.material.name + " angle of repose: a slope cut steeper fails until it rests at it"});
  const double dug_r_mid = finite_mean(dug_cone.bin_r_half), r_mid = finite_mean(wall.bin_r_half);
  if (std::isfinite(dug_r_mid) && std::isfinite(r_mid)) {
    // The profiles as dug and settled, each from its wall's point at half its depth, and the
    // material's slope through that point.
    r.series.push_back(profile("as dug", height_map(as_dug, 0, Material::Granular), bed.half, dug_r_mid,
                               bed.depth - dug_cone.height_cells / 2, true));
    const Series settled_profile = profile("settled", height_map(settled, 0, Material::Granular), bed.half, r_mid,
                                           bed.depth - wall.height_cells / 2, false);
    r.series.push_back(settled_profile);
    const double t = std::tan(o.material.repose_deg * std::numbers::pi / 180);
    r.series.push_back({o.material.name + " at " + std::to_string(int(o.material.repose_deg)) + " deg",
                        settled_profile.x_label, settled_profile.y_label, {-0.5 * bed.radius, 0.5 * bed.radius},
                        {-0.5 * bed.radius * t, 0.5 * bed.radius * t}, true});
  }
  Series per_bin{"wall angle per azimuth bin", "azimuth (deg)", "wall angle (deg)", {}, {}, false};
  for (int k = 0; k < kConeAzimuthBins; ++k)
    if (std::isfinite(wall.bin_angle_deg[std::size_t(k)])) {
      per_bin.x.push_back((k + 0.5) * 360.0 / kConeAzimuthBins);
      per_bin.y.push_back(wall.bin_angle_deg[std::size_t(k)]);
    }
  r.series.push_back(per_bin);
  r.series.push_back({"target " + o.material.name, "azimuth (deg)", "wall angle (deg)", {0, 360},
                      {o.material.repose_deg, o.material.repose_deg}, true});
  char line[320];
  std::snprintf(line, sizeof line,
                "as dug: depth %.0f cells, walls %.1f deg; settled after %llu ticks: depth %.0f cells, walls %.2f deg "
                "(spread %.2f over %d bins), radius at half depth %.1f cells (r_max/r_min %.3f); %llu grains dug out",
                dug_cone.height_cells, dug_cone.angle_deg, static_cast<unsigned long long>(rest.ticks), wall.height_cells,
                wall.angle_deg, wall.angle_spread_deg, wall.bins, r_mid, wall.r_half_ratio,
                static_cast<unsigned long long>(removed));
  r.notes.push_back(line);
  if (const AxisDiagonalAngles a = axis_diagonal_angles(wall); a.ok) {
    std::snprintf(line, sizeof line, "wall angle near the axes %.1f deg, near the diagonals %.1f deg", a.axis_deg,
                  a.diagonal_deg);
    r.notes.push_back(line);
  }
  if (!bed_rest.settled) r.notes.push_back("the bed had not come to rest before the dig");
  if (!rest.settled) r.notes.push_back("the crater had not come to rest within " + std::to_string(limit) + " ticks");
  return r;
}

}  // namespace granular::accuracy
