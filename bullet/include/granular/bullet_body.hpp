#pragma once
/// @file bullet_body.hpp
/// A World body in Bullet's units and back: the collision shape, mass and rigid body a BodyDef
/// stands for, and the BodyDef a rigid body's shape and mass stand for. BulletCoupling::add reads a
/// rigid body this way; a game that must give a rigid body to a World body that exists already (one
/// an undo or a snapshot brought back) builds it with make_bullet_body and hands it to
/// BulletCoupling::couple (docs/design/bodies.md, "Bullet").

#include <memory>

#include "granular/body.hpp"

class btCollisionShape;
class btDefaultMotionState;
class btRigidBody;

namespace granular {

/// Bullet's collision shape for `def`'s shape in metres, for cells of `cell_metres`: a btBoxShape of
/// `half_extents` (its margin inside them), a btSphereShape of `radius` or a btCapsuleShapeZ of
/// `radius` and `half_length`. Throws InvalidArgument for a size that is not finite and > 0 (a
/// capsule's half_length >= 0) or a cell_metres that is not.
std::unique_ptr<btCollisionShape> bullet_shape(const BodyDef& def, double cell_metres);

/// The mass of `def` in kg: its density times its shape's volume (shape_volume) in cubic metres.
double body_mass(const BodyDef& def, double cell_metres);

/// The BodyDef that Bullet's `shape` with `mass` (kg) stands for, for cells of `cell_metres`: its
/// shape and size, and the density that gives that mass (pose left at its default). Throws
/// InvalidArgument for a shape other than btBoxShape, btSphereShape and btCapsuleShapeZ, or a mass
/// that is not finite and > 0.
BodyDef body_def_of(const btCollisionShape& shape, double mass, double cell_metres);

/// A rigid body for a World body, with the collision shape and motion state it borrows. The rigid
/// body is in no dynamics world until the game adds it; remove it from there before this goes.
struct BulletBody {
  std::unique_ptr<btCollisionShape> shape;       ///< bullet_shape of the def
  std::unique_ptr<btDefaultMotionState> motion;  ///< the motion state `rigid` reads its first pose from
  std::unique_ptr<btRigidBody> rigid;            ///< the rigid body of body_mass and the shape's inertia

  /// An empty one (no shape, motion state or rigid body).
  BulletBody();
  /// Frees the rigid body, then its motion state and shape.
  ~BulletBody();
  /// Takes `other`'s objects.
  BulletBody(BulletBody&& other) noexcept;
  /// Frees this one's objects and takes `other`'s.
  BulletBody& operator=(BulletBody&& other) noexcept;
};

/// A rigid body of `def`'s shape and mass at `def.pose`: position and orientation in metres, velocity
/// and spin per second, for cells of `cell_metres` and ticks of `tick_seconds`. Throws
/// InvalidArgument as bullet_shape does, or for a tick_seconds that is not finite and > 0.
BulletBody make_bullet_body(const BodyDef& def, double cell_metres, double tick_seconds);

}  // namespace granular
