#include "renderers/marching_cubes_tables.hpp"

#include <cstdint>
#include <algorithm>
#include <stdexcept>
#include <vector>

namespace viewer {
namespace {

constexpr std::array<std::array<int, 2>, 12> make_edges() {
  std::array<std::array<int, 2>, 12> edges{};
  for (int axis = 0; axis < 3; ++axis) {
    int k = 0;
    for (int c = 0; c < 8; ++c)
      if (!(c & (1 << axis))) edges[axis * 4 + k++] = {c, c | (1 << axis)};
  }
  return edges;
}

int edge_between(int a, int b) {
  for (int e = 0; e < 12; ++e)
    if ((kEdgeCorners[e][0] == a && kEdgeCorners[e][1] == b) || (kEdgeCorners[e][0] == b && kEdgeCorners[e][1] == a)) return e;
  throw std::logic_error("marching cubes: corners are not adjacent");
}

struct Vec {
  double x, y, z;
};

/// True when edges a and b lie on one face of the cube (all four corners share a coordinate).
bool on_one_face(int a, int b) {
  const int corners[4] = {kEdgeCorners[a][0], kEdgeCorners[a][1], kEdgeCorners[b][0], kEdgeCorners[b][1]};
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      bool all = true;
      for (int c : corners) all = all && ((c >> axis) & 1) == side;
      if (all) return true;
    }
  return false;
}

/// Rotates `loop` so that a fan from its first vertex adds no diagonal lying in a cube face (such a
/// triangle would overlap the neighbouring cube's surface instead of meeting it at an edge).
void choose_fan_apex(std::vector<int>& loop) {
  const std::size_t n = loop.size();
  for (std::size_t apex = 0; apex < n; ++apex) {
    bool clean = true;
    for (std::size_t i = 2; i + 1 < n && clean; ++i) clean = !on_one_face(loop[apex], loop[(apex + i) % n]);
    if (clean) {
      std::rotate(loop.begin(), loop.begin() + std::ptrdiff_t(apex), loop.end());
      return;
    }
  }
}

Vec edge_midpoint(int e) {
  const int a = kEdgeCorners[e][0], b = kEdgeCorners[e][1];
  return {((a & 1) + (b & 1)) * 0.5, (((a >> 1) & 1) + ((b >> 1) & 1)) * 0.5, (((a >> 2) & 1) + ((b >> 2) & 1)) * 0.5};
}

MarchingCase make_case(int mask) {
  auto inside = [&](int corner) { return (mask >> corner) & 1; };
  // successor[e]: the edge that follows crossing edge e along its loop (-1: e does not cross).
  std::array<int, 12> successor;
  successor.fill(-1);
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      std::array<int, 4> ring{};
      const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int k = 0; k < 4; ++k) {
        const int j = side ? k : 3 - k;  // counter-clockwise seen from outside the cube
        ring[k] = (side << axis) | (uv[j][0] << u) | (uv[j][1] << v);
      }
      for (int k = 0; k < 4; ++k) {
        if (inside(ring[k]) || !inside(ring[(k + 1) % 4])) continue;  // not an entering crossing
        for (int step = 1; step < 4; ++step) {
          const int from = ring[(k + step) % 4], to = ring[(k + step + 1) % 4];
          if (inside(from) && !inside(to)) {
            successor[edge_between(ring[k], ring[(k + 1) % 4])] = edge_between(from, to);
            break;
          }
        }
      }
    }
  }
  MarchingCase result;
  std::array<bool, 12> used{};
  for (int start = 0; start < 12; ++start) {
    if (successor[start] < 0 || used[start]) continue;
    std::vector<int> loop;
    for (int e = start; !used[e]; e = successor[e]) {
      used[e] = true;
      loop.push_back(e);
    }
    choose_fan_apex(loop);
    // Orient the fan so that its summed normal points from the loop's inside corners (one end of
    // each of its edges) to its outside corners.
    Vec outward{0, 0, 0};
    for (int e : loop)
      for (int end = 0; end < 2; ++end) {
        const int corner = kEdgeCorners[e][end];
        const double sign = inside(corner) ? -1.0 : 1.0;
        outward.x += sign * (corner & 1);
        outward.y += sign * ((corner >> 1) & 1);
        outward.z += sign * ((corner >> 2) & 1);
      }
    double facing = 0;
    const Vec a = edge_midpoint(loop[0]);
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
      const Vec b = edge_midpoint(loop[i]), c = edge_midpoint(loop[i + 1]);
      const Vec ab{b.x - a.x, b.y - a.y, b.z - a.z}, ac{c.x - a.x, c.y - a.y, c.z - a.z};
      const Vec n{ab.y * ac.z - ab.z * ac.y, ab.z * ac.x - ab.x * ac.z, ab.x * ac.y - ab.y * ac.x};
      facing += n.x * outward.x + n.y * outward.y + n.z * outward.z;
    }
    const bool flip = facing < 0;
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
      if (result.edge_count + 3 > kMaxCaseEdges) throw std::logic_error("marching cubes: case table overflow");
      result.edges[result.edge_count++] = std::uint32_t(loop[0]);
      result.edges[result.edge_count++] = std::uint32_t(flip ? loop[i + 1] : loop[i]);
      result.edges[result.edge_count++] = std::uint32_t(flip ? loop[i] : loop[i + 1]);
    }
  }
  return result;
}

}  // namespace

const std::array<std::array<int, 2>, 12> kEdgeCorners = make_edges();

const std::array<MarchingCase, 256>& marching_cases() {
  static const std::array<MarchingCase, 256> cases = [] {
    std::array<MarchingCase, 256> table;
    for (int mask = 0; mask < 256; ++mask) table[mask] = make_case(mask);
    return table;
  }();
  return cases;
}

}  // namespace viewer
