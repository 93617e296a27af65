#pragma once
/// @file body_stamp.hpp
/// Writing a body into the grid for one tick: the cells it left become void, the cells of its shape
/// become its material, and the grains, liquid and gas in their way are pushed out along paths to the
/// nearest free cells, each cell of a path moving one cell on (docs/design/bodies.md, "Displacement").

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "granular/geometry.hpp"
#include "granular/material.hpp"
#include "granular/rule_set.hpp"

namespace granular {

/// Cells around a body's bounds that its pushes may pass through and end in.
inline constexpr int kBodyReach = 4;

/// What stamp_body did.
struct StampResult {
  std::int64_t blocked = 0;    ///< cells of the shape not taken (static, or no free cell within reach)
  MaterialCounts displaced{};  ///< cells pushed out of the shape, per material
  MaterialCounts filled{};     ///< cells of the wake filled, per material
};

/// The scratch of stamp_body, reused from body to body. Each task has its own, a cache line apart
/// from the next task's, so that tasks do not share lines they write.
struct alignas(64) StampScratch {
  std::vector<std::uint8_t> in_shape;  ///< per cell of the region: outside the shape, in it, or the body's
  std::vector<std::uint64_t> rows;     ///< for_each_cell_beside's bit rows
  std::vector<std::uint32_t> queue;    ///< the last search's cells, in the order reached
  std::vector<Int3> shape_at;          ///< the shape's cells as coordinates
  std::vector<Int3> owned_at;          ///< the held cells as coordinates
  std::vector<std::uint32_t> push;     ///< the shape's cells to empty, as indices into it
  std::vector<std::pair<double, std::uint32_t>> ahead;  ///< the pushes with how far ahead they lie, to sort
  std::vector<std::uint64_t> taken;                     ///< grid indices of the cells the body holds after the stamp
  std::vector<std::uint32_t> left;                      ///< local indices of the cells the body left
  std::vector<std::uint8_t> parent;                     ///< per cell the last search reached: the direction it came in
  std::vector<std::uint8_t> dead;                       ///< per cell: a search from it finds nothing
  std::vector<std::uint8_t> edges;                      ///< per cell: which of its neighbours lie outside the region
  Int3 edges_extent{};                                  ///< the extent of the region `edges` is for
  std::vector<std::uint8_t> cls;             ///< per cell: what the searches ask of it (void, liquid, passable...)
  std::vector<std::uint32_t> distance;       ///< per cell: the number of the search that reached it, and its steps to
                                             ///< the nearest void a push may end in
  std::uint32_t searched = 0;                ///< the number of the last search of the distances (1..255)
  std::vector<std::uint64_t> pending;        ///< bit rows: the starts of the pushes still to come
  std::vector<std::uint64_t> passable;       ///< that search's bit rows: the cells a push may pass
  std::vector<std::uint64_t> reached;        ///< the cells it has reached
  std::vector<std::uint64_t> at_distance;    ///< the cells at the distance it is at
  std::vector<std::uint64_t> next_distance;  ///< the cells at the next one
  std::vector<std::uint64_t> no_rows;        ///< a layer's rows of no cells: beyond the region's
  std::vector<std::uint32_t> route;          ///< one push's cells, from the shape to the void
  std::vector<std::uint32_t> written;        ///< local indices of the cells the stamp wrote (some twice)
};

/// Writes a body into `bytes`, the cell bytes (x fastest) of `region`, which (inside a grid of `grid`)
/// holds every cell of `owned` and `shape` (grid indices, ascending) and kBodyReach cells around them
/// where the grid has them; scratch.written lists the cells it wrote:
/// - a cell of `owned` outside `shape` that still holds `body_material` becomes void;
/// - a cell of `shape` that is void, or is in `owned` and holds `body_material`, becomes (stays) the body's;
/// - a cell of `shape` holding a mobile material (granular, liquid, gas in `materials`) is emptied
///   along the shortest path of mobile cells and voids not yet the body's to a void outside the
///   shape, every cell of the path moving one cell towards that void (at rest), then becomes the
///   body's. The void is the nearest one away from the body's surroundings (kRingWidth cells beside
///   its layers, which its buoyancy reads) where the region has one, else the nearest in them. The
///   front of the body goes first; ties go to the direction of `motion` (cells), then up, then
///   sideways in an order drawn per cell from `salt` (no side is favoured);
/// - every other cell of `shape` (static, or with no such path) is blocked and left as it is;
/// - each cell the body left is filled, lowest first, from the nearest surface of liquid higher than
///   it (liquid outside the shape with void or gas over it; away from the surroundings first) along
///   a path of liquid, each cell moving one cell on, so water closes behind a moving body and its
///   surface drops; grains are left to topple in by the rules.
/// `owned` becomes the cells the body holds, ascending. Mass is conserved: every path shifts cells
/// by one, into a void or out of the cell that becomes void.
StampResult stamp_body(const Box& region, std::span<std::uint8_t> bytes, Int3 grid,
                       const std::vector<std::uint64_t>& shape, std::vector<std::uint64_t>& owned,
                       std::uint8_t body_material, const MaterialTable& materials, const Vec3& motion,
                       std::uint64_t salt, StampScratch& scratch);

}  // namespace granular
