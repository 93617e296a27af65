#pragma once
/// @file sphere_runs.hpp
/// The cells of a box whose centres lie in a sphere, as one run per row: the walk the sphere tools
/// (World::dig, pour, paint, shake) share.

#include <algorithm>
#include <cmath>

#include "granular/geometry.hpp"

namespace granular {

/// Calls fn(y, z, first, last), in ascending (z, y), for each row (y, z) of `region` holding a cell
/// whose centre lies in `s` (dx * dx + dy * dy + dz * dz <= r * r in doubles): those are the
/// cells x in [first, last). Rounding is monotonic, so along a row the sum only grows away from the
/// cell holding the centre's x (clamped to the region), and the cells inside are one run around
/// it. A row whose dy * dy + dz * dz alone exceeds r * r holds none, nor one whose cell nearest the
/// centre fails the test; otherwise each end of the run starts where the square root puts it and
/// the test moves it to the last cell where it holds.
template <class Fn>
void walk_runs_in_sphere(const Box& region, const Sphere& s, Fn&& fn) {
  const double r2 = s.radius * s.radius;
  const int nearest = int(std::clamp(std::floor(s.center.x), double(region.min.x), double(region.max.x - 1)));
  for (int z = region.min.z; z < region.max.z; ++z)
    for (int y = region.min.y; y < region.max.y; ++y) {
      const double dy = y + 0.5 - s.center.y, dz = z + 0.5 - s.center.z;
      const double dy2 = dy * dy, dz2 = dz * dz;
      if (dy2 + dz2 > r2) continue;
      const auto inside = [&](int x) {
        const double dx = x + 0.5 - s.center.x;
        return dx * dx + dy2 + dz2 <= r2;
      };
      if (!inside(nearest)) continue;
      // In reals the run holds the x with |x + 0.5 - centre| <= half: from ceil(centre - 0.5 - half),
      // the truncation of centre + 0.5 - half clamped to the region unless that is whole, to before
      // floor(centre + 0.5 + half). Rounding may move an end (by a cell, for a sphere of ordinary
      // size); both guesses lie on the run's side of `nearest`, so the test settles each end.
      // (std::max: the difference under the root may round below 0.)
      const double half = std::sqrt(std::max(0.0, r2 - dy2 - dz2));
      int first = int(std::clamp(s.center.x + 0.5 - half, double(region.min.x), double(nearest)));
      int last = int(std::clamp(s.center.x + 0.5 + half, double(nearest + 1), double(region.max.x)));
      while (first > region.min.x && inside(first - 1)) --first;
      while (!inside(first)) ++first;
      while (last < region.max.x && inside(last)) ++last;
      while (!inside(last - 1)) --last;
      fn(y, z, first, last);
    }
}

/// walk_runs_in_sphere of `region`, a box of a grid whose cell (0, 0, 0) is cell `origin` of a
/// larger world, for a sphere in that world's coordinates: the walk is the larger world's, to the
/// cell, and fn gets the grid's own coordinates.
template <class Fn>
void for_each_run_in_sphere(const Box& region, const Sphere& s, Fn&& fn, Int3 origin = {}) {
  const Box moved{{region.min.x + origin.x, region.min.y + origin.y, region.min.z + origin.z},
                  {region.max.x + origin.x, region.max.y + origin.y, region.max.z + origin.z}};
  walk_runs_in_sphere(moved, s, [&](int y, int z, int first, int last) {
    fn(y - origin.y, z - origin.z, first - origin.x, last - origin.x);
  });
}

}  // namespace granular
