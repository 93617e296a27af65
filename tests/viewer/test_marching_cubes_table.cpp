#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <map>
#include <random>
#include <utility>

#include "renderers/marching_cubes_tables.hpp"

using namespace viewer;

namespace {

bool crosses(int mask, int edge) {
  return ((mask >> kEdgeCorners[edge][0]) & 1) != ((mask >> kEdgeCorners[edge][1]) & 1);
}

}  // namespace

TEST_CASE("marching cubes table: each case uses exactly its crossing edges") {
  for (int mask = 0; mask < 256; ++mask) {
    CAPTURE(mask);
    const MarchingCase& c = marching_cases()[mask];
    CHECK(c.edge_count % 3 == 0);
    std::array<bool, 12> used{};
    for (std::uint32_t k = 0; k < c.edge_count; ++k) {
      REQUIRE(c.edges[k] < 12);
      CHECK(crosses(mask, int(c.edges[k])));
      used[c.edges[k]] = true;
    }
    for (int e = 0; e < 12; ++e) CHECK(used[e] == crosses(mask, e));
  }
  CHECK(marching_cases()[0].edge_count == 0);
  CHECK(marching_cases()[255].edge_count == 0);
}

TEST_CASE("marching cubes table: the surface of any inside set is closed and consistently oriented") {
  // Lattice of n^3 points, inside at random (the border outside so the surface closes); every mesh
  // edge must be shared by exactly two triangles that traverse it in opposite directions.
  constexpr int n = 9;
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    std::array<std::uint8_t, n * n * n> inside{};
    for (int z = 1; z < n - 1; ++z)
      for (int y = 1; y < n - 1; ++y)
        for (int x = 1; x < n - 1; ++x) inside[x + n * (y + n * z)] = (rng() % 100) < 45;
    // A vertex is a lattice edge: (lowest corner, axis).
    auto vertex_id = [&](int cx, int cy, int cz, int edge) {
      const int a = kEdgeCorners[edge][0];
      const int axis = edge / 4;
      return ((cx + (a & 1)) + n * ((cy + ((a >> 1) & 1)) + n * (cz + ((a >> 2) & 1)))) * 3 + axis;
    };
    std::map<std::pair<int, int>, int> directed;  // (from, to) -> count
    for (int z = 0; z + 1 < n; ++z)
      for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
          int mask = 0;
          for (int c = 0; c < 8; ++c)
            mask |= inside[(x + (c & 1)) + n * ((y + ((c >> 1) & 1)) + n * (z + ((c >> 2) & 1)))] << c;
          const MarchingCase& mc = marching_cases()[mask];
          for (std::uint32_t t = 0; t < mc.edge_count; t += 3) {
            const int v[3] = {vertex_id(x, y, z, int(mc.edges[t])), vertex_id(x, y, z, int(mc.edges[t + 1])),
                              vertex_id(x, y, z, int(mc.edges[t + 2]))};
            for (int k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
          }
        }
    REQUIRE(!directed.empty());
    for (const auto& [edge, count] : directed) {
      CHECK(count == 1);
      const auto back = directed.find({edge.second, edge.first});
      CHECK((back != directed.end() && back->second == 1));
    }
  }
}

TEST_CASE("marching cubes table: triangles face away from the inside corners") {
  // Corner 0 alone inside: the one triangle's normal points towards (1, 1, 1).
  const MarchingCase& c = marching_cases()[1];
  REQUIRE(c.edge_count == 3);
  auto midpoint = [](std::uint32_t e) {
    const int a = kEdgeCorners[e][0], b = kEdgeCorners[e][1];
    return std::array<double, 3>{((a & 1) + (b & 1)) * 0.5, (((a >> 1) & 1) + ((b >> 1) & 1)) * 0.5,
                                 (((a >> 2) & 1) + ((b >> 2) & 1)) * 0.5};
  };
  const auto p0 = midpoint(c.edges[0]), p1 = midpoint(c.edges[1]), p2 = midpoint(c.edges[2]);
  const std::array<double, 3> u{p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, v{p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
  const std::array<double, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  CHECK(n[0] + n[1] + n[2] > 0);
}
