#pragma once
/// @file head_field.hpp
/// The hydraulic head of the liquids (MotionParams::pressure), per coarse cell of 2 x 2 x 2 cells:
/// the plane of state beside the cell bytes that the block step reads to give a liquid its pressure.
/// Plain constexpr integer code: the CPU backend and the CUDA kernels compute the same field from the
/// same cells, and the block step reads it the same way on both.
///
/// What the field holds. Only the liquid of a body counts: a liquid at motion level 0 standing on
/// something other than a void or a gas (a falling jet is in free flight; at_rest_liquid and the
/// support test in seed). A coarse cell holding none is dry (kDry). One holding some starts at its
/// *seed*: the highest free surface among its liquid cells (z + 1 of a liquid cell with a void or a
/// gas straight above it, in kUnit per cell), or kSunk when none of them has one. The head then
/// spreads through the liquid: a coarse cell takes the head of a face neighbour it is joined to,
/// less kWetStep units per coarse step, when that is higher than its own. Two coarse cells
/// are joined when a liquid cell on their common face has a liquid cell across it. At the fixed
/// point each coarse cell holds the highest free surface of its liquid body, less a small penalty
/// for the distance to it: a connected body at rest has one head, its surface; a body whose
/// surfaces stand at different heights has the head of its highest one everywhere, so a lower
/// surface lies under its head and the block step lets the liquid under it rise (fluid_block.hpp,
/// the pressure stage), and the penalty makes the head fall towards the highest surface, which is
/// where the voids left behind travel.
///
/// The solver is a fixed list of passes (sweep_pass): kSweepRounds rounds of one pass along +x, -x,
/// +y, -y, +z and -z, each carrying the head along whole lines of coarse cells (a line is one
/// sequential loop; lines run in parallel), then kDryRounds rounds that carry each body's head out
/// into the dry coarse cells beside and above it, less kDryStep a coarse step and marked odd: a
/// liquid the head pushes out of its body still feels it where it lands before the next solve. A
/// path through the liquid with k turns reaches its end in k + 1 rounds whatever its length, so the
/// cost is bounded at every size; a body joined only by a more winding path than kSweepRounds rounds
/// follow gets the head of its part of the path.

#include <cstdint>

#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/motion.hpp"
#include "step/step_materials.hpp"

namespace granular::head {

/// The edge of a coarse cell, in cells (coarse cell (i, j, k) holds cells 2i .. 2i + 1 along x, ...).
inline constexpr int kCoarseEdge = 2;
/// Head units per cell of height.
inline constexpr std::int32_t kUnit = 1024;
/// The head of a coarse cell that holds no liquid.
inline constexpr std::int32_t kDry = INT32_MIN;
static_assert(std::int64_t(kMaxGridExtent + 2) * kUnit < (std::int64_t(1) << 30),
              "a head of any cell of a grid, in kUnit, lies far above kSunk and far below INT32_MAX");
/// The seed of a coarse cell whose liquid has no free surface: below every real head, so any joined
/// neighbour's head replaces it; far enough above kDry that the penalty never reaches it.
inline constexpr std::int32_t kSunk = -(1 << 30);
/// Sweep rounds of the solver through the liquid (each: +x, -x, +y, -y, +z, -z).
inline constexpr int kSweepRounds = 3;
/// Rounds of the solver that carry a body's head out into dry coarse cells (each: +x, -x, +y, -y,
/// +z): the head a liquid pushed out of its body meets where it lands within the tick.
inline constexpr int kDryRounds = 2;
/// Head units a wet coarse step costs (even, so a wet head stays even: head_of and carried_out).
inline constexpr std::int32_t kWetStep = 2;
/// Head units a dry coarse step costs: 1/4 cell each 2 cells, so a head reaches 4 (e - 1) coarse
/// cells out of its body at a height e cells under it.
inline constexpr std::int32_t kDryStep = kUnit / 4;

/// One pass of the solver: along `axis` (0: x, 1: y, 2: z), `forward` or backward, through the
/// liquid (`dry` false) or out into dry coarse cells (`dry` true).
struct SweepPass {
  int axis;      ///< 0: x, 1: y, 2: z
  bool forward;  ///< towards increasing index
  bool dry;      ///< carry heads into dry coarse cells (dilate) instead of through the liquid
};

/// The solver's passes in order, which every backend runs: kSweepRounds rounds of +x, -x, +y, -y,
/// +z, -z through the liquid, then kDryRounds rounds of +x, -x, +y, -y, +z out into the dry coarse
/// cells (up, never down: a liquid leaving its body downwards is in free fall).
inline constexpr int kPassCount = 6 * kSweepRounds + 5 * kDryRounds;

/// Pass `n` (0 .. kPassCount - 1) of the solver.
constexpr SweepPass sweep_pass(int n) {
  if (n < 6 * kSweepRounds) return {(n % 6) / 2, n % 2 == 0, false};
  const int d = (n - 6 * kSweepRounds) % 5;
  return {d / 2, d % 2 == 0, true};
}

/// True when a head read by the block step lies outside any body: a dry coarse cell (kDry) or one
/// the solver carried a head into from a body (odd: carried_out).
constexpr bool outside_body(std::int32_t h) { return h == kDry || (h & 1) != 0; }
/// Link bits of a coarse cell: joined to its +x, +y, +z neighbour.
inline constexpr std::uint8_t kLinkX = 1, kLinkY = 2, kLinkZ = 4;

/// The coarse grid of a grid of `size` cells.
constexpr Int3 coarse_size(Int3 size) { return {(size.x + 1) / 2, (size.y + 1) / 2, (size.z + 1) / 2}; }

/// The index of coarse cell (i, j, k) in a coarse grid of `c` (x fastest).
constexpr std::int64_t coarse_index(Int3 c, int i, int j, int k) {
  return std::int64_t(i) + std::int64_t(c.x) * (std::int64_t(j) + std::int64_t(c.y) * std::int64_t(k));
}

/// The index of the coarse cell of cell (x, y, z) (inside the grid) in a coarse grid of `c`.
constexpr std::int64_t coarse_of_cell(Int3 c, int x, int y, int z) { return coarse_index(c, x >> 1, y >> 1, z >> 1); }

/// True when cell byte `cell` is a liquid at motion level 0: a liquid in the body. A liquid that
/// falls, or was set moving, is in free flight: it takes no part in the head (neither its seed nor
/// its links) and no pressure move, so a jet leaving an orifice is not pushed back up into it.
constexpr bool at_rest_liquid(const StepMaterials& m, std::uint32_t cell) {
  return m.is_liquid(cell & kMaterialMask) && ((cell >> kMotionShift) & kMotionLevelMask) == 0;
}

/// The seed and links of coarse cell (i, j, k): `at(x, y, z)` reads a cell byte of the grid of
/// `size` (only inside it). Sets `links` (kLinkX | kLinkY | kLinkZ) and returns the seed (kDry,
/// kSunk or a surface in kUnit).
template <class At>
constexpr std::int32_t seed(At at, Int3 size, const StepMaterials& m, int i, int j, int k, std::uint8_t& links) {
  std::int32_t s = kDry;
  links = 0;
  const int x0 = 2 * i, y0 = 2 * j, z0 = 2 * k;
  // A liquid at rest on something that is not a lighter fluid: one over a void is falling.
  auto liquid = [&](int x, int y, int z) {
    if (!at_rest_liquid(m, std::uint32_t(at(x, y, z)))) return false;
    if (z == 0) return true;
    const std::uint32_t below = std::uint32_t(at(x, y, z - 1)) & kMaterialMask;
    return !(m.is_fluid(below) && !m.is_liquid(below));
  };
  for (int z = z0; z < z0 + 2 && z < size.z; ++z)
    for (int y = y0; y < y0 + 2 && y < size.y; ++y)
      for (int x = x0; x < x0 + 2 && x < size.x; ++x) {
        if (!liquid(x, y, z)) continue;
        if (s == kDry) s = kSunk;
        if (z + 1 < size.z) {
          const std::uint32_t above = std::uint32_t(at(x, y, z + 1)) & kMaterialMask;
          if (m.is_fluid(above) && !m.is_liquid(above) && (z + 1) * kUnit > s) s = (z + 1) * kUnit;
        }
        if (x == x0 + 1 && x + 1 < size.x && liquid(x + 1, y, z)) links |= kLinkX;
        if (y == y0 + 1 && y + 1 < size.y && liquid(x, y + 1, z)) links |= kLinkY;
        if (z == z0 + 1 && z + 1 < size.z && liquid(x, y, z + 1)) links |= kLinkZ;
      }
  return s;
}

/// One pass (sweep_pass) along a line of `count` coarse cells starting at `first`, `stride` apart,
/// in the direction of increasing index (`forward`) or decreasing. Through the liquid (`dry` false)
/// each cell takes its predecessor's head less kWetStep when the two are joined (bit `link` of the
/// lower one's links) and that is higher. Out of the body (`dry` true) a dry coarse cell (kDry or
/// already carried into) takes its predecessor's head (a body's or carried) less kDryStep, marked
/// odd (outside_body), when that is higher; a wet cell keeps its own. `heads` and `links` are
/// indexable (plain pointers on both backends).
template <class Heads, class Links>
constexpr void sweep_line(Heads heads, Links links, std::int64_t first, std::int64_t stride, int count, std::uint8_t link,
                          bool forward, bool dry = false) {
  const std::int64_t step = forward ? stride : -stride;
  const std::int64_t start = forward ? first : first + stride * (count - 1);
  for (int n = 1; n < count; ++n) {
    const std::int64_t here = start + step * n, before = here - step;
    const std::int32_t from = heads[before];
    if (from <= kSunk) continue;  // dry (kDry) or a liquid with no surface: nothing to carry
    if (!dry) {
      const std::int64_t lower = forward ? before : here;
      if ((links[lower] & link) == 0) continue;
      const std::int32_t carried = from - kWetStep;
      if (carried > heads[here]) heads[here] = carried;
    } else {
      if (!outside_body(heads[here])) continue;
      const std::int32_t carried = ((from & ~1) - kDryStep) | 1;
      if (carried > heads[here]) heads[here] = carried;
    }
  }
}

/// floor(sqrt(e)) for a head excess of `excess` units (e = excess / kUnit cells), at most 64.
constexpr int root_cells(std::int32_t excess) {
  int r = 0;
  while (r < 64 && std::int64_t(r + 1) * (r + 1) * kUnit <= std::int64_t(excess)) ++r;
  return r;
}

/// True when a head `excess` units above a target's top pushes a liquid into it in sub-step
/// `substep`: in the first 4 sqrt(e) sub-steps of each tick for a move up or down (`vertical`), the
/// first 6 sqrt(e) for a move sideways, e the excess in cells. A cell finds its target in its block
/// one sub-step in two, so a liquid moves under a head at up to 2 sqrt(e) = sqrt(2 g e) cells a tick
/// up or down (g = 2 cells per tick^2: Torricelli's exit speed) and 3 sqrt(e) sideways (Ritter's
/// front, 2 sqrt(g e) = 2.8 sqrt(e)): speeds that grow as the square root of the head. Under
/// MotionParams::momentum's schedule (x and y flip in about 3 of 4 sub-steps) the sideways push meets
/// its target in about 3 in 4 of those sub-steps: up to about 4.5 sqrt(e) cells a tick.
constexpr bool pushes(std::int32_t excess, int substep, bool vertical) {
  // substep < k sqrt(e)  <=>  substep^2 < k^2 e
  const std::int64_t k2 = vertical ? 16 : 36;
  return std::int64_t(substep) * substep * kUnit < k2 * std::int64_t(excess);
}

/// The motion level of a liquid pushed down out of its body under a head `excess` units above the
/// cell it enters: the level whose window (motion_window) is its exit speed 2 sqrt(e) cells a tick,
/// at most `max_level`.
constexpr int exit_level(std::int32_t excess, int max_level) {
  const int level = root_cells(excess) + 1;  // window 2 L - 1 = 2 sqrt(e) + 1
  return level < max_level ? level : max_level;
}

}  // namespace granular::head

namespace granular::head {

/// True when a pressure move may start in coarse cell (i, j, k) of head `h`: one of its liquid cells
/// has a void or a lighter fluid beside it (x or y) or above it whose top lies below the head
/// (h > kUnit (z + 1) of that cell), the fluid pass's pressure condition. `at` reads the grid of
/// `size`. A backend keeps the bricks of such coarse cells awake (sparse stepping): the pressure
/// stage has no draw, so a block where no move may start stays as it is while the heads stay.
template <class At>
constexpr bool may_press(At at, Int3 size, const StepMaterials& m, int i, int j, int k, std::int32_t h) {
  if (h <= kSunk) return false;
  const int x0 = 2 * i, y0 = 2 * j, z0 = 2 * k;
  for (int z = z0; z < z0 + 2 && z < size.z; ++z) {
    if (h <= (z + 1) * kUnit) continue;  // no target in this layer or above it lies under the head
    for (int y = y0; y < y0 + 2 && y < size.y; ++y)
      for (int x = x0; x < x0 + 2 && x < size.x; ++x) {
        const std::uint32_t cell = std::uint32_t(at(x, y, z)), a = cell & kMaterialMask;
        if (!at_rest_liquid(m, cell)) continue;
        auto lighter = [&](int bx, int by, int bz) {
          if (bx < 0 || by < 0 || bx >= size.x || by >= size.y || bz >= size.z) return false;
          const std::uint32_t b = std::uint32_t(at(bx, by, bz)) & kMaterialMask;
          return m.is_fluid(b) && !m.is_liquid(b) && m.density[b] < m.density[a];
        };
        if (lighter(x - 1, y, z) || lighter(x + 1, y, z) || lighter(x, y - 1, z) || lighter(x, y + 1, z)) return true;
        if (h > (z + 2) * kUnit && lighter(x, y, z + 1)) return true;
      }
  }
  return false;
}

}  // namespace granular::head
