#pragma once
/// @file marching_cubes_tables.hpp
/// The marching-cubes case table, generated rather than typed in: for each of the 256 inside/outside
/// patterns of a cube's corners, the triangles (as cube edges) that separate inside from outside.
/// Loops are found by walking the six faces; on an ambiguous face (two diagonal inside corners) the
/// inside corners are cut off separately, a rule that only depends on the face, so neighbouring cubes
/// agree and the surface has no cracks. Triangles face the outside.

#include <array>
#include <cstdint>

namespace viewer {

/// Corner c of a cube sits at (c & 1, (c >> 1) & 1, (c >> 2) & 1).
/// Edge e joins corners kEdgeCorners[e][0] and [1]; edges 4a..4a+3 run along axis a.
extern const std::array<std::array<int, 2>, 12> kEdgeCorners;

/// Most edge entries one case needs (3 per triangle).
inline constexpr int kMaxCaseEdges = 15;

/// One case: `edge_count` edge indices, three per triangle.
struct MarchingCase {
  std::uint32_t edge_count = 0;                     ///< multiple of 3
  std::array<std::uint32_t, kMaxCaseEdges> edges{};  ///< edge indices
};

/// The 256 cases, indexed by the bit mask of inside corners (bit c = corner c inside).
const std::array<MarchingCase, 256>& marching_cases();

}  // namespace viewer
