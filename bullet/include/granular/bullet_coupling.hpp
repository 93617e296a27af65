#pragma once
/// @file bullet_coupling.hpp
/// Bullet rigid bodies in the sand: a BulletCoupling keeps the rigid bodies of a
/// btDiscreteDynamicsWorld and the bodies of a granular World in step, one fixed tick at a time.
/// Bullet moves them (gravity, contacts between them, their inertia) and the sand pushes back
/// (World::body_sand's buoyancy and drag, applied as forces); the static cells near each body
/// collide in Bullet as boxes. An optional module: granular's core never links Bullet
/// (docs/design/bodies.md, "Bullet"). bullet_body.hpp converts between World bodies and rigid bodies.

#include <cstdint>
#include <memory>
#include <vector>

#include "granular/body.hpp"
#include "granular/world.hpp"

class btBoxShape;
class btCollisionObject;
class btCompoundShape;
class btDiscreteDynamicsWorld;
class btRigidBody;

namespace granular {

/// The settings of a BulletCoupling.
struct BulletCouplingDef {
  int substeps = 4;       ///< Bullet steps per world tick (>= 1)
  int static_margin = 3;  ///< cells around a body and its path over the coming tick whose static cells
                          ///< collide in Bullet (1..32)
};

/// What BulletCoupling::sync found after the World's bodies changed without the coupling.
struct CouplingSync {
  /// Rigid bodies whose World body is gone (or whose handle names another body now): no longer
  /// coupled, still in the dynamics world (the game removes them from it and frees them).
  std::vector<btRigidBody*> uncoupled;
  /// The World's bodies that no rigid body is coupled with, ascending: the game makes a rigid body for
  /// each (make_bullet_body of World::body_def), adds it to the dynamics world and couple()s it.
  std::vector<BodyId> unmatched;
};

/// Couples the rigid bodies of a Bullet dynamics world with the bodies of a World. Bullet's units
/// are metres and seconds, z up (set the dynamics world's gravity to (0, 0, -9.81)); the World's
/// cell (i, j, k) spans [i, i+1) x [j, j+1) x [k, k+1) times WorldDef::cell_metres from Bullet's
/// origin. Neither world is owned; both must outlive the coupling.
class BulletCoupling {
 public:
  /// Couples `world` and `dynamics`. Throws InvalidArgument for settings out of range.
  BulletCoupling(World& world, btDiscreteDynamicsWorld& dynamics, const BulletCouplingDef& def = {});
  ~BulletCoupling();
  BulletCoupling(const BulletCoupling&) = delete;
  BulletCoupling& operator=(const BulletCoupling&) = delete;

  /// Adds a World body for `rigid` (already in the dynamics world, not static), from its collision
  /// shape (btBoxShape, btSphereShape or btCapsuleShapeZ), its mass (density = mass / volume) and its
  /// pose. Throws InvalidArgument for another shape, a static rigid body, or one coupled already.
  BodyId add(btRigidBody& rigid);
  /// Removes the World body of `rigid` (its cells become void); the rigid body stays in Bullet.
  /// Throws InvalidArgument when it is not coupled.
  void remove(btRigidBody& rigid);
  /// The World body of `rigid`. Throws InvalidArgument when it is not coupled.
  BodyId body_of(const btRigidBody& rigid) const;
  /// Couples `rigid` (already in the dynamics world, not static) with `body`, a body the World holds
  /// already and no rigid body is coupled with: one that an undo, World::restore or the game's own
  /// World::add_body made. `rigid` takes the World body's pose, velocity and spin; its shape and mass
  /// must be the body's (body_def_of them equals World::body_def's shape, sizes and density to a
  /// relative 1e-4, as make_bullet_body builds them). Throws InvalidArgument for an unknown body, a
  /// body or rigid body coupled already, a static rigid body, or a shape or mass not the body's.
  void couple(btRigidBody& rigid, BodyId body);
  /// Brings the coupling up to date after the World's bodies changed without it (World::restore, a
  /// StrokeHistory undo or redo, World::remove_body or add_body called on the world): uncouples the
  /// rigid bodies whose World body is gone, or whose handle now names a body of another shape, size
  /// or density (an undo or a restore gives handles back), gives every other rigid body its World
  /// body's pose, velocity and spin (and drops the forces applied to it since Bullet last stepped),
  /// and lists the World bodies without a rigid body. Changes nothing in the World, so a
  /// StrokeHistory can still redo after it.
  CouplingSync sync();
  /// The rigid bodies coupled now, in the order they were coupled.
  std::vector<btRigidBody*> rigid_bodies() const;

  /// One fixed tick: each rigid body's pose and velocity go to its World body, the World steps one
  /// tick (writing the bodies into the grid and pushing the sand aside), each rigid body feels its
  /// BodySand force and torque, the static cells near the bodies (and their paths over the tick)
  /// become Bullet's collision boxes (the body material's cells among them, but for those the
  /// coupled bodies hold: a game's structure of that material, or a body it moves itself, collides), Bullet steps the tick's length (tick_seconds of the World's
  /// rules) in `substeps` steps, and each World body takes its rigid body's new pose and velocity, so
  /// that between steps the World's bodies (body_pose, capture(), a StrokeHistory) are Bullet's.
  void step();

  /// The boxes the static cells near the bodies collide as, after the last step().
  std::size_t static_boxes() const;

 private:
  struct Coupled {
    btRigidBody* rigid = nullptr;
    BodyId body = 0;
  };
  void write_poses();
  void read_pose(btRigidBody& rigid, BodyId body) const;
  bool matches(const btRigidBody& rigid, const BodyDef& def) const;
  void apply_forces();
  void rebuild_statics();

  World& world_;
  btDiscreteDynamicsWorld& dynamics_;
  BulletCouplingDef def_;
  double cell_m_;
  double tick_s_;
  std::vector<Coupled> coupled_;
  std::unique_ptr<btCompoundShape> statics_shape_;
  std::unique_ptr<btCollisionObject> statics_;
  std::vector<std::unique_ptr<btBoxShape>> boxes_;
  std::uint64_t statics_key_ = 0;  ///< a hash of the boxes now in statics_shape_
};

}  // namespace granular
