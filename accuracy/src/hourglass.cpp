#include "hourglass.hpp"

#include <algorithm>
#include <chrono>

#include "granular/scene.hpp"
#include "granular/world.hpp"

namespace granular::accuracy {

namespace {

/// Grains at z >= z_neck.
double grains_above(const World& world, int z_neck) {
  const Int3 s = world.size();
  const std::vector<std::uint8_t> cells = world.read_region(Box{{0, 0, z_neck}, s});
  return double(std::count(cells.begin(), cells.end(), to_cell(Material::Granular)));
}

}  // namespace

HourglassDischarge hourglass_discharge(const SuiteOptions& o, int n) {
  HourglassDischarge h;
  h.n = n;
  const SceneInstance scene = instantiate(load_scene(find_scene("hourglass")), n);
  const Int3 size = scene.grid.size();
  World world(test_world_def(o, size), scene.grid);
  const MaterialCounts before = world.count();
  const int z_neck = size.z / 2;
  const double initial = grains_above(world, z_neck);
  std::vector<double> ticks{0}, left{initial};
  const std::uint64_t limit = 400ull * std::uint64_t(n);
  const auto start = std::chrono::steady_clock::now();
  while (h.ticks < limit) {
    world.step(1);
    h.ticks += 1;
    ticks.push_back(double(h.ticks));
    left.push_back(grains_above(world, z_neck));
    if (left.back() <= 0.2 * initial) {
      h.drained = true;
      break;
    }
  }
  h.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  h.cell_updates = double(size.x) * size.y * size.z * double(h.ticks);
  h.conserved = world.count() == before;
  // When `fraction` of the initial upper count had left, interpolated between samples.
  auto tick_at = [&](double fraction) {
    const double target = fraction * initial;
    for (std::size_t i = 1; i < left.size(); ++i) {
      const double gone0 = initial - left[i - 1], gone1 = initial - left[i];
      if (gone1 >= target && gone1 > gone0)
        return ticks[i - 1] + (ticks[i] - ticks[i - 1]) * std::clamp((target - gone0) / (gone1 - gone0), 0.0, 1.0);
    }
    return -1.0;
  };
  for (int w = 2; w < 8; ++w) {
    const double t0 = tick_at(0.1 * w), t1 = tick_at(0.1 * (w + 1));
    if (t0 < 0 || t1 <= t0) continue;
    h.emptied.push_back(0.1 * w + 0.05);
    h.rate.push_back(0.1 * initial / (t1 - t0));
  }
  if (!h.rate.empty()) {
    double sum = 0;
    for (double v : h.rate) sum += v;
    h.mean_rate = sum / double(h.rate.size());
    const auto [lo, hi] = std::minmax_element(h.rate.begin(), h.rate.end());
    h.spread = (*hi - *lo) / h.mean_rate;
  }
  return h;
}

}  // namespace granular::accuracy
