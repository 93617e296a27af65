#pragma once
/// @file bullet_coupling.hpp
/// Bullet rigid bodies in the sand: a BulletCoupling keeps the rigid bodies of a
/// btDiscreteDynamicsWorld and the bodies of a granular World in step, one fixed tick at a time.
/// Bullet moves them (gravity, contacts between them, their inertia) and the sand pushes back
/// (World::body_sand's buoyancy and drag, applied as forces); the static cells near each body
/// collide in Bullet as boxes. An optional module: granular's core never links Bullet
/// (docs/design/bodies.md, "Bullet").

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
  int static_margin = 3;  ///< cells around a body whose static cells collide in Bullet (>= 1)
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

  /// One fixed tick: each rigid body's pose and velocity go to its World body, the World steps one
  /// tick (writing the bodies into the grid and pushing the sand aside), each rigid body feels its
  /// BodySand force and torque, the static cells near the bodies become Bullet's collision boxes,
  /// and Bullet steps the tick's length (tick_seconds of the World's rules) in `substeps` steps.
  void step();

  /// The boxes the static cells near the bodies collide as, after the last step().
  std::size_t static_boxes() const;

 private:
  struct Coupled {
    btRigidBody* rigid = nullptr;
    BodyId body = 0;
  };
  void write_poses();
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
