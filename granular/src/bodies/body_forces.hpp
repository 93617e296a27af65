#pragma once
/// @file body_forces.hpp
/// What the sand does to a body it holds cells of: what it is submerged in and rests on, and the
/// buoyancy and drag of its surroundings (docs/design/bodies.md, "Forces").

#include <cstdint>
#include <span>
#include <vector>

#include "granular/body.hpp"
#include "granular/rule_set.hpp"

namespace granular {

/// How far beside a layer of a body its surroundings reach, in cells (x and y).
inline constexpr int kRingWidth = 2;

/// The physical scale of cells and ticks.
struct BodyScale {
  double cell_m = 0.005;   ///< a cell's edge, metres
  double tick_s = 0.0319;  ///< a tick, seconds
  double gravity = 9.81;   ///< m/s^2
};

/// The scratch of sand_forces, reused from body to body. Each task has its own, a cache line apart
/// from the next task's, so that tasks do not share lines they write.
struct alignas(64) ForceScratch {
  std::vector<std::uint8_t> owned;  ///< per cell of the region: held by the body
  std::vector<std::uint64_t> rows;  ///< for_each_cell_beside's bit rows
  std::vector<Int3> owned_at;       ///< the held cells as coordinates
};

/// Fills `sand`'s cells, submerged, below, buoyancy, drag, force and torque for a body holding the
/// cells `owned` (grid indices, ascending, of a grid of `grid`) of the region `box`, whose cell bytes
/// are `bytes` (x fastest; the body and kBodyReach cells around it where the grid has them), at `pose`, of
/// mass `mass` kg and moment of inertia `moment` kg m^2, having pushed `sand.displaced` out of its
/// way this tick:
/// - each layer of the body is submerged in the materials of the non-static cells within
///   kRingWidth cells beside it in that layer, in their proportions, and is buoyed by their bulk density
///   (MaterialDef::body); the lift is given as an implicit step over the tick gives it, for a body whose
///   weight m g pulls it down, so that a light body whose lift changes steeply with its height settles
///   instead of swinging further each tick;
/// - each face of it against a material, moving at normal speed u and speed w along itself, feels a
///   pressure 1/2 drag rho (|u| + c) u against u (ahead of the body and, as suction, behind it) and a
///   shear of a tenth of that for w, where c = sqrt(g cell) is the speed of a gravity wave a cell
///   deep (so slow swings are damped), and the cells it pushed take `push` of their momentum at the
///   body's speed;
/// - the drag D against momentum p is given as D / (1 + D dt / p) (likewise the torque), the change
///   of an implicit step over the tick dt: an engine stepping it explicitly slows the body as the
///   drag would, and never turns it back.
void sand_forces(const Box& box, std::span<const std::uint8_t> bytes, Int3 grid,
                 const std::vector<std::uint64_t>& owned, const MaterialTable& materials, const BodyPose& pose,
                 double mass, double moment, const BodyScale& scale, BodySand& sand, ForceScratch& scratch);

}  // namespace granular
