#pragma once
/// @file body.hpp
/// Rigid bodies in the sand: shapes a game adds to a World and moves each tick (itself, or through
/// a physics engine), which the world writes into the grid as obstacles, pushing what is in their
/// way aside, and whose contact with the sand it reports as forces (docs/design/bodies.md).

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "granular/geometry.hpp"
#include "granular/material.hpp"

namespace granular {

/// A rotation as a unit quaternion w + xi + yj + zk (World normalises it).
struct Quat {
  double w = 1;  ///< real part
  double x = 0;  ///< i
  double y = 0;  ///< j
  double z = 0;  ///< k
  friend constexpr bool operator==(const Quat&, const Quat&) = default;
};

/// The shape of a body, in its own frame (centred on its position).
enum class BodyShape : std::uint8_t {
  Box = 0,      ///< a box of BodyDef::half_extents
  Sphere = 1,   ///< a ball of BodyDef::radius
  Capsule = 2,  ///< a segment of BodyDef::half_length along the body's z axis, swept by BodyDef::radius
};

/// Where a body is and how fast it moves, in cell units (docs/design/bodies.md, "Units").
struct BodyPose {
  Vec3 position;          ///< the shape's centre, in cells (cell (i, j, k) spans [i, i+1) x ...)
  Quat orientation;       ///< rotation from the body's frame to the world's
  Vec3 velocity;          ///< cells per tick: the pose moves this far after each tick the body is written in
  Vec3 angular_velocity;  ///< radians per tick about the centre, in the world's frame
};

/// What a body is: its shape, size, density and first pose. Every field has a usable default.
struct BodyDef {
  BodyShape shape = BodyShape::Box;  ///< the shape
  Vec3 half_extents{4, 4, 4};        ///< Box: half its edge lengths along the body's axes, in cells (> 0)
  double radius = 4;                 ///< Sphere and Capsule: the radius, in cells (> 0)
  double half_length = 4;            ///< Capsule: half the length of its axis segment, in cells (>= 0)
  double density = 1000;             ///< kg/m^3 (> 0): the mass the forces are clamped against
  BodyPose pose;                     ///< where it starts
};

/// The largest half size (BodyDef::half_extents, radius, half_length), in cells.
inline constexpr double kMaxBodyHalfSize = 64;
/// The largest speed of a body's centre, in cells per tick (a body that moves farther than its reach
/// in a tick leaves its old cells and is written anew where it lands).
inline constexpr double kMaxBodySpeed = 4096;
/// The largest spin of a body, in radians per tick.
inline constexpr double kMaxBodySpin = 64;
/// The most bodies one World holds.
inline constexpr std::size_t kMaxBodies = 4096;

/// The volume of `def`'s shape, in cells^3 (its mass is that times WorldDef::cell_metres^3 times
/// BodyDef::density).
double shape_volume(const BodyDef& def);

/// A body's handle, given by World::add_body; never reused by one World.
using BodyId = std::uint32_t;

/// What the sand did with a body and to it in one tick: the cells it took and pushed, what it is
/// submerged in and rests on, and the forces of the sand on it (docs/design/bodies.md, "Forces").
/// Forces are in newtons and torques in newton metres about the body's position, in the world's
/// frame, for cells of WorldDef::cell_metres and ticks of tick_seconds(); gravity on the body itself
/// is not in them (the game or engine applies it).
struct BodySand {
  std::uint64_t tick = 0;      ///< the tick at whose start the body was written
  std::int64_t cells = 0;      ///< cells the body holds in the grid
  std::int64_t blocked = 0;    ///< cells of its shape it did not take: static cells (walls, other bodies)
                               ///< and cells whose grains had no free cell to go to within reach
  MaterialCounts displaced{};  ///< cells pushed out of the body's new volume this tick, per material
  std::array<double, kMaterialCount> submerged{};  ///< cells of the body below the surface of each
                                                   ///< material around it (fractions per layer)
  MaterialCounts below{};                          ///< the cells right under the body's lowest cells, per material
  Vec3 buoyancy;    ///< the bulk density of what surrounds each of its layers, times g and the layer's volume (N)
  Vec3 drag;        ///< drag of its faces and the momentum of what it pushed (N), as an implicit
                    ///< step over the tick gives it: it slows the body and never turns it back
  Vec3 force;       ///< buoyancy + drag (N)
  Vec3 torque;      ///< of buoyancy and drag about the position (N m)
  double mass = 0;  ///< the body's mass, density times its shape's volume (kg)
};

/// One body as a snapshot or an undo keeps it: all a World needs to go on writing it into the grid
/// exactly as it would have.
struct BodyState {
  BodyId id = 0;                     ///< its handle
  BodyDef def;                       ///< what it is; def.pose is where it is written at the next tick
  std::vector<std::uint64_t> cells;  ///< grid indices (x fastest, ascending) of the cells it holds
};

/// Every body of a World (World::body_states, WorldSnapshot::bodies).
struct BodyStates {
  std::vector<BodyState> bodies;  ///< in the order they were added
  BodyId next_id = 1;             ///< the handle the next add_body gives
};

}  // namespace granular
