#include "granular/raycast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/world.hpp"

namespace granular {
namespace {

using CellReader = std::function<Material(Int3)>;

void check_ray(Vec3 origin, Vec3 direction, double max_distance) {
  if (!std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.z))
    throw InvalidArgument("raycast: the origin must be finite");
  const double length = std::sqrt(direction.x * direction.x + direction.y * direction.y + direction.z * direction.z);
  if (!std::isfinite(length) || length == 0) throw InvalidArgument("raycast: the direction must be finite and non-zero");
  if (!(max_distance >= 0)) throw InvalidArgument("raycast: max_distance must be >= 0");
}

// Amanatides & Woo: clip the ray to the grid box, then step from cell to cell across the nearest
// boundary until a non-void cell, the far side of the box, or max_distance.
std::optional<RayHit> march(Int3 size, const CellReader& read, Vec3 origin, Vec3 direction, double max_distance) {
  check_ray(origin, direction, max_distance);
  const double length = std::sqrt(direction.x * direction.x + direction.y * direction.y + direction.z * direction.z);
  const double o[3] = {origin.x, origin.y, origin.z};
  const double d[3] = {direction.x / length, direction.y / length, direction.z / length};
  const int extent[3] = {size.x, size.y, size.z};
  double t_enter = 0, t_exit = max_distance;
  int enter_axis = -1;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < 0 || o[a] >= extent[a]) return std::nullopt;
      continue;
    }
    double t0 = (0 - o[a]) / d[a], t1 = (extent[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_enter) {
      t_enter = t0;
      enter_axis = a;
    }
    t_exit = std::min(t_exit, t1);
  }
  if (t_enter > t_exit) return std::nullopt;
  int cell[3], step[3];
  double t_max[3], t_delta[3];
  for (int a = 0; a < 3; ++a) {
    const double p = o[a] + d[a] * t_enter;
    cell[a] = std::clamp(int(std::floor(p)), 0, extent[a] - 1);
    if (a == enter_axis) cell[a] = d[a] > 0 ? 0 : extent[a] - 1;
    step[a] = d[a] > 0 ? 1 : (d[a] < 0 ? -1 : 0);
    t_delta[a] = d[a] != 0 ? std::abs(1.0 / d[a]) : std::numeric_limits<double>::infinity();
    t_max[a] = d[a] != 0 ? ((cell[a] + (step[a] > 0 ? 1 : 0)) - o[a]) / d[a] : std::numeric_limits<double>::infinity();
  }
  double t = t_enter;
  int axis = enter_axis;
  while (t <= t_exit) {
    const Int3 here{cell[0], cell[1], cell[2]};
    const Material m = read(here);
    if (m != Material::Void) {
      RayHit hit;
      hit.cell = here;
      hit.material = m;
      hit.distance = t;
      hit.point = {o[0] + d[0] * t, o[1] + d[1] * t, o[2] + d[2] * t};
      if (axis >= 0) {
        int n[3] = {0, 0, 0};
        n[axis] = -step[axis];
        hit.normal = {n[0], n[1], n[2]};
      }
      return hit;
    }
    axis = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    t = t_max[axis];
    cell[axis] += step[axis];
    t_max[axis] += t_delta[axis];
    if (cell[axis] < 0 || cell[axis] >= extent[axis]) break;
  }
  return std::nullopt;
}

}  // namespace

std::optional<RayHit> raycast(const World& world, Vec3 origin, Vec3 direction, double max_distance) {
  const Int3 size = world.size();
  const Int3 counts = world.brick_counts();
  std::int64_t cached_brick = -1;
  Box cached_box{};
  std::vector<std::uint8_t> cached;
  const CellReader read = [&](Int3 p) {
    const std::int64_t brick = std::int64_t(p.x / kBrickSize) +
                               std::int64_t(counts.x) * (p.y / kBrickSize + std::int64_t(counts.y) * (p.z / kBrickSize));
    if (brick != cached_brick) {
      cached_brick = brick;
      cached_box = brick_box(size, std::uint32_t(brick));
      cached = world.read_region(cached_box);
    }
    const Int3 e = cached_box.extent();
    const Int3 l{p.x - cached_box.min.x, p.y - cached_box.min.y, p.z - cached_box.min.z};
    return Material(cached[std::size_t(l.x) + std::size_t(e.x) * (std::size_t(l.y) + std::size_t(e.y) * std::size_t(l.z))]);
  };
  return march(size, read, origin, direction, max_distance);
}

std::optional<RayHit> raycast(const Grid& grid, Vec3 origin, Vec3 direction, double max_distance) {
  return march(grid.size(), [&](Int3 p) { return grid.at(p); }, origin, direction, max_distance);
}

}  // namespace granular
