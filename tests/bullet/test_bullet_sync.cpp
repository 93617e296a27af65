/// @file test_bullet_sync.cpp
/// granular::bullet beside World changes it did not make: bodies as Bullet shapes and back
/// (bullet_body.hpp), BulletCoupling::couple for a World body that exists already, and
/// BulletCoupling::sync after World::remove_body, add_body, a StrokeHistory undo and redo, and
/// World::restore. Runs as the ctest entry bullet.sync (built with Bullet).

#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <btBulletDynamicsCommon.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "granular/bullet_body.hpp"
#include "granular/bullet_coupling.hpp"
#include "granular/errors.hpp"
#include "granular/stroke_history.hpp"
#include "granular/time_scale.hpp"
#include "granular/world.hpp"

using namespace granular;

namespace {

/// A 40^3 world with a bed of sand 12 cells deep, and Bullet beside it.
struct Scene {
  std::unique_ptr<World> world;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld dynamics{&dispatcher, &broadphase, &solver, &configuration};
  std::unique_ptr<BulletCoupling> coupling;
  std::vector<BulletBody> bodies;
  double cell = 0, tick = 0;

  Scene() {
    WorldDef def;
    def.backend = BackendKind::Cpu;
    def.size = {40, 40, 40};
    world = std::make_unique<World>(def);
    world->paint(Box{{0, 0, 0}, {40, 40, 12}}, Material::Granular);
    dynamics.setGravity(btVector3(0, 0, -9.81f));
    coupling = std::make_unique<BulletCoupling>(*world, dynamics);
    cell = def.cell_metres;
    tick = tick_seconds(world->rules(), cell);
  }
  ~Scene() {
    coupling.reset();
    for (BulletBody& b : bodies) dynamics.removeRigidBody(b.rigid.get());
  }
  /// A rigid body for World body `id`, in Bullet and kept.
  btRigidBody& rigid_for(BodyId id) {
    bodies.push_back(make_bullet_body(world->body_def(id), cell, tick));
    dynamics.addRigidBody(bodies.back().rigid.get());
    return *bodies.back().rigid;
  }
  /// Takes `rigid` out of Bullet and frees it.
  void drop(btRigidBody* rigid) {
    dynamics.removeRigidBody(rigid);
    std::erase_if(bodies, [&](const BulletBody& b) { return b.rigid.get() == rigid; });
  }
};

BodyDef crate(Vec3 position, Vec3 velocity = {}) {
  BodyDef def;
  def.shape = BodyShape::Box;
  def.half_extents = {3, 4, 5};
  def.density = 700;
  def.pose.position = position;
  def.pose.velocity = velocity;
  return def;
}

}  // namespace

TEST_CASE("bullet body: a body's shape and mass in Bullet give back its def") {
  constexpr double cell = 0.005;
  BodyDef box = crate({});
  BodyDef sphere;
  sphere.shape = BodyShape::Sphere;
  sphere.radius = 4.5;
  sphere.density = 7800;
  BodyDef capsule;
  capsule.shape = BodyShape::Capsule;
  capsule.radius = 3;
  capsule.half_length = 5;
  capsule.density = 300;
  for (const BodyDef& def : {box, sphere, capsule}) {
    const auto shape = bullet_shape(def, cell);
    const BodyDef back = body_def_of(*shape, body_mass(def, cell), cell);
    CHECK(back.shape == def.shape);
    CHECK(back.density == doctest::Approx(def.density).epsilon(1e-5));
    CHECK(shape_volume(back) == doctest::Approx(shape_volume(def)).epsilon(1e-5));
  }
  CHECK(body_mass(box, cell) == doctest::Approx(700 * 6 * 8 * 10 * cell * cell * cell));
  BodyDef flat = box;
  flat.half_extents.y = 0;
  CHECK_THROWS_AS(bullet_shape(flat, cell), InvalidArgument);
  CHECK_THROWS_AS(bullet_shape(box, 0), InvalidArgument);
  btCylinderShapeZ cylinder(btVector3(0.01f, 0.01f, 0.02f));
  CHECK_THROWS_WITH_AS(body_def_of(cylinder, 1.0, cell), doctest::Contains("not a btBoxShape"), InvalidArgument);
  CHECK_THROWS_AS(body_def_of(*bullet_shape(box, cell), 0.0, cell), InvalidArgument);
}

TEST_CASE("bullet sync: a World body added without Bullet is listed, coupled, and moved by Bullet") {
  Scene s;
  const BodyId id = s.world->add_body(crate({20, 20, 30}, {0.5, 0, 0}));
  CouplingSync found = s.coupling->sync();
  CHECK(found.uncoupled.empty());
  REQUIRE(found.unmatched == std::vector<BodyId>{id});
  btRigidBody& rigid = s.rigid_for(id);
  s.coupling->couple(rigid, id);
  CHECK(s.coupling->body_of(rigid) == id);
  CHECK(rigid.getWorldTransform().getOrigin().z() == doctest::Approx(30 * s.cell));
  CHECK(rigid.getLinearVelocity().x() == doctest::Approx(0.5 * s.cell / s.tick));
  CHECK(s.coupling->sync().unmatched.empty());
  for (int t = 0; t < 5; ++t) s.coupling->step();
  CHECK(s.world->body_pose(id).position.z < 29);  // falls
  CHECK(s.world->body_pose(id).position.x > 21);  // and flies on

  // What couple refuses, each with the coupling unchanged.
  CHECK_THROWS_WITH_AS(s.coupling->couple(rigid, id), doctest::Contains("coupled already"), InvalidArgument);
  const BodyId other = s.world->add_body(crate({10, 10, 30}));
  btRigidBody& wrong = s.rigid_for(id);  // the first body's shape: the same, but `other` is coupled by nobody
  CHECK_THROWS_WITH_AS(s.coupling->couple(wrong, 999), doctest::Contains("999"), InvalidArgument);
  BodyDef heavier = s.world->body_def(other);
  heavier.density *= 2;
  s.bodies.push_back(make_bullet_body(heavier, s.cell, s.tick));
  s.dynamics.addRigidBody(s.bodies.back().rigid.get());
  CHECK_THROWS_WITH_AS(s.coupling->couple(*s.bodies.back().rigid, other), doctest::Contains("shape or mass"),
                       InvalidArgument);
  s.coupling->couple(wrong, other);  // same shape and mass as `other`: fine
  CHECK(s.coupling->rigid_bodies().size() == 2);
}

TEST_CASE("bullet sync: a removed World body's rigid body is handed back; a restore brings back its pose") {
  Scene s;
  const BodyId a = s.world->add_body(crate({12, 20, 30}));
  const BodyId b = s.world->add_body(crate({28, 20, 30}));
  for (const BodyId id : s.coupling->sync().unmatched) s.coupling->couple(s.rigid_for(id), id);
  for (int t = 0; t < 4; ++t) s.coupling->step();
  const WorldSnapshot early = s.world->capture();
  const BodyPose a_early = s.world->body_pose(a);
  for (int t = 0; t < 30; ++t) s.coupling->step();
  btRigidBody* rigid_b = s.coupling->rigid_bodies()[1];
  s.world->remove_body(b);
  const CouplingSync found = s.coupling->sync();
  REQUIRE(found.uncoupled == std::vector<btRigidBody*>{rigid_b});
  CHECK(found.unmatched.empty());
  s.drop(rigid_b);
  CHECK(s.coupling->rigid_bodies().size() == 1);
  s.coupling->step();

  s.world->restore(early);  // both bodies as they were 30 ticks ago
  const CouplingSync restored = s.coupling->sync();
  CHECK(restored.uncoupled.empty());  // a is the World's still, moved back
  REQUIRE(restored.unmatched == std::vector<BodyId>{b});
  s.coupling->couple(s.rigid_for(b), b);
  const btRigidBody* rigid_a = s.coupling->rigid_bodies()[0];
  CHECK(rigid_a->getWorldTransform().getOrigin().z() == doctest::Approx(a_early.position.z * s.cell));
  CHECK(rigid_a->getLinearVelocity().z() == doctest::Approx(a_early.velocity.z * s.cell / s.tick));
  for (int t = 0; t < 3; ++t) s.coupling->step();
  CHECK(s.world->body_ids().size() == 2);
}

TEST_CASE("bullet sync: after an undo the thrown body's rigid body goes; sync keeps the redo, which brings it back") {
  Scene s;
  StrokeHistory history(*s.world);
  s.world->step(2);
  history.begin_stroke();
  s.bodies.push_back(make_bullet_body(crate({20, 20, 32}, {0, 0.3, 0}), s.cell, s.tick));
  btRigidBody* thrown = s.bodies.back().rigid.get();
  s.dynamics.addRigidBody(thrown);
  const BodyId id = s.coupling->add(*thrown);
  history.end_stroke();
  for (int t = 0; t < 12; ++t) s.coupling->step();

  REQUIRE(history.undo());
  CHECK(s.world->body_ids().empty());
  const CouplingSync undone = s.coupling->sync();
  REQUIRE(undone.uncoupled == std::vector<btRigidBody*>{thrown});
  s.drop(thrown);
  REQUIRE(history.redo());  // sync changed nothing in the World
  const CouplingSync redone = s.coupling->sync();
  REQUIRE(redone.unmatched == std::vector<BodyId>{id});
  s.coupling->couple(s.rigid_for(id), id);
  CHECK(s.world->body_pose(id).position.z == doctest::Approx(32));
  for (int t = 0; t < 12; ++t) s.coupling->step();
  CHECK(s.world->body_pose(id).position.z < 28);
}

TEST_CASE("bullet sync: a handle a restore gives back to a body of another shape gets a rigid body of its own") {
  Scene s;
  const WorldSnapshot empty = s.world->capture();
  const BodyId crate_id = s.world->add_body(crate({20, 20, 30}));
  for (const BodyId id : s.coupling->sync().unmatched) s.coupling->couple(s.rigid_for(id), id);
  s.coupling->step();
  const WorldSnapshot with_crate = s.world->capture();
  s.world->restore(empty);
  BodyDef ball;
  ball.shape = BodyShape::Sphere;
  ball.radius = 4;
  ball.density = 2000;
  ball.pose.position = {10, 10, 30};
  const BodyId ball_id = s.world->add_body(ball);  // may take the crate's handle back
  btRigidBody* crate_rigid = s.coupling->rigid_bodies()[0];
  const CouplingSync found = s.coupling->sync();
  REQUIRE(found.uncoupled == std::vector<btRigidBody*>{crate_rigid});
  REQUIRE(found.unmatched == std::vector<BodyId>{ball_id});
  s.drop(crate_rigid);
  s.coupling->couple(s.rigid_for(ball_id), ball_id);
  s.world->restore(with_crate);
  const CouplingSync back = s.coupling->sync();
  CHECK(back.uncoupled.size() == 1);
  REQUIRE(back.unmatched == std::vector<BodyId>{crate_id});
}

TEST_CASE("bullet statics: a wall painted in the body material stops a body Bullet throws at it") {
  Scene scene;
  // A wall of state 7, the body material, across the world at x = 24..27, over the bed.
  scene.world->paint(Box{{24, 0, 12}, {28, 40, 36}}, Material::State7);
  BodyDef ball;
  ball.shape = BodyShape::Sphere;
  ball.radius = 3;
  ball.density = 2000;
  ball.pose.position = {12, 20, 28};
  const BodyId id = scene.world->add_body(ball);
  btRigidBody& rigid = scene.rigid_for(id);
  scene.coupling->couple(rigid, id);
  rigid.setLinearVelocity(btVector3(btScalar(3 * scene.cell / scene.tick), 0, 0));  // 3 cells a tick along x
  double farthest = 0;
  for (int t = 0; t < 60; ++t) {
    scene.coupling->step();
    farthest = std::max(farthest, scene.world->body_pose(id).position.x);
  }
  MESSAGE("ball thrown at the wall: farthest centre x " << farthest << " (wall from x = 24; radius 3)");
  CHECK(farthest < 24 - 3 + 1);  // stopped within a cell of touching the wall
  CHECK(scene.coupling->static_boxes() > 0);
}
