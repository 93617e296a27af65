/// @file test_sphere_runs.cpp
/// for_each_run_in_sphere, the sphere tools' walk: its runs are exactly the cells whose centres
/// pass the sphere test, cell by cell, for spheres whose surface passes through a cell centre to
/// within rounding (where the square root's guess of a run's end and the test disagree), clipped
/// ones included.

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "granular/errors.hpp"
#include "world/sphere_runs.hpp"
#include "world/tool_region.hpp"

using namespace granular;

TEST_CASE("sphere runs: the runs hold exactly the cells the sphere test holds, at the surface too") {
  const Int3 size{48, 40, 36};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coord(-4.0, 52.0), offset(-9.0, 9.0);
  std::uniform_int_distribution<int> ulps(-3, 3);
  for (int round = 0; round < 4000; ++round) {
    CAPTURE(round);
    Sphere s{{coord(rng), coord(rng), coord(rng)}, 0};
    // The surface through (or within a few ulps of) the centre of a cell near the sphere's centre.
    const double dx = std::floor(s.center.x + offset(rng)) + 0.5 - s.center.x;
    const double dy = std::floor(s.center.y + offset(rng)) + 0.5 - s.center.y;
    const double dz = std::floor(s.center.z + offset(rng)) + 0.5 - s.center.z;
    s.radius = std::sqrt(dx * dx + dy * dy + dz * dz);
    for (int u = ulps(rng); u != 0; u += u > 0 ? -1 : 1) s.radius = std::nextafter(s.radius, u > 0 ? 1e9 : 0.0);
    if (!(s.radius > 0)) continue;
    bool clipped = false;
    Box region;
    try {
      region = sphere_region(s, size, "test", clipped);
    } catch (const InvalidArgument&) {
      continue;  // misses the grid
    }
    const Int3 e = region.extent();
    std::vector<char> in_runs(std::size_t(region.volume()), 0);
    int last_row = -1;
    for_each_run_in_sphere(region, s, [&](int y, int z, int first, int last) {
      const int row = (z - region.min.z) * e.y + (y - region.min.y);
      CHECK(row > last_row);  // ascending rows, one run each
      last_row = row;
      CHECK(region.min.x <= first);
      CHECK(first < last);
      CHECK(last <= region.max.x);
      for (int x = first; x < last; ++x)
        in_runs[std::size_t(row) * std::size_t(e.x) + std::size_t(x - region.min.x)] = 1;
    });
    for (int z = region.min.z; z < region.max.z; ++z)
      for (int y = region.min.y; y < region.max.y; ++y)
        for (int x = region.min.x; x < region.max.x; ++x) {
          const double cx = x + 0.5 - s.center.x, cy = y + 0.5 - s.center.y, cz = z + 0.5 - s.center.z;
          const bool inside = cx * cx + cy * cy + cz * cz <= s.radius * s.radius;
          const std::size_t i = (std::size_t(z - region.min.z) * std::size_t(e.y) + std::size_t(y - region.min.y)) *
                                    std::size_t(e.x) + std::size_t(x - region.min.x);
          if ((in_runs[i] != 0) != inside) {
            CAPTURE(x);
            CAPTURE(y);
            CAPTURE(z);
            FAIL("a cell's place in the runs differs from the sphere test");
          }
        }
  }
}
