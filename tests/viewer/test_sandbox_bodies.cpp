/// @file test_sandbox_bodies.cpp
/// The sandbox's bodies in Bullet (bodies/sandbox_bodies.hpp, built with Bullet): Bullet and the World
/// step in lockstep, thrown bodies never leave the grid whatever way they fly, light ones float and
/// heavy ones sink, the count is capped, and after an undo, a redo or a restore Bullet holds exactly
/// the World's bodies again. No window.

#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include "bodies/body_throw.hpp"
#include "bodies/sandbox_bodies.hpp"
#include "granular/errors.hpp"
#include "granular/stroke_history.hpp"
#include "granular/time_scale.hpp"
#include "granular/world.hpp"

using namespace viewer;

namespace {

constexpr int kN = 48;

/// A 48^3 world with a bed of sand 16 cells deep over its floor.
std::unique_ptr<granular::World> sand_bed() {
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {kN, kN, kN};
  auto world = std::make_unique<granular::World>(def);
  world->paint(granular::Box{{0, 0, 0}, {kN, kN, 16}}, granular::Material::Granular);
  return world;
}

/// A ball of `radius` cells and `density` at `position`, flying at `velocity` cells per tick.
granular::BodyDef ball(granular::Vec3 position, granular::Vec3 velocity, double density = 800, double radius = 4) {
  granular::BodyDef def;
  def.shape = granular::BodyShape::Sphere;
  def.radius = radius;
  def.density = density;
  def.pose.position = position;
  def.pose.velocity = velocity;
  return def;
}

}  // namespace

TEST_CASE("sandbox bodies: Bullet steps with the world, a tick at a time, and the world holds Bullet's pose") {
  auto world = sand_bed();
  SandboxBodies bodies(*world);
  bodies.step(3);  // no body: World::step(3)
  CHECK(world->tick() == 3);
  const granular::BodyId id = bodies.add(ball({24, 24, 44}, {0, 0, 0}));
  CHECK(bodies.count() == 1);
  double last_z = 44;
  for (int tick = 0; tick < 4; ++tick) {
    bodies.step(1);
    const granular::BodyPose pose = world->body_pose(id);
    CHECK(pose.position.z < last_z);  // falls under Bullet's gravity, tick by tick
    last_z = pose.position.z;
  }
  CHECK(world->tick() == 7);
  // Four ticks of free fall from rest, above the bed: g t^2 / 2 = 9.81 * (4 ticks)^2 / 2.
  const double t = 4 * granular::tick_seconds(world->rules(), world->def().cell_metres);
  const double fallen_cells = 9.81 * t * t / 2 / world->def().cell_metres;
  CHECK(fallen_cells == doctest::Approx(16.0).epsilon(0.01));
  CHECK(44 - last_z == doctest::Approx(fallen_cells).epsilon(0.1));
}

TEST_CASE("sandbox bodies: thrown hard at each face of the grid, a body stays inside it") {
  const granular::Vec3 directions[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const granular::Vec3 d : directions) {
    auto world = sand_bed();
    SandboxBodies bodies(*world);
    const double speed = 20;  // cells a tick: 3.1 m/s, faster than any throw
    const granular::BodyId id = bodies.add(ball({24, 24, 32}, {d.x * speed, d.y * speed, d.z * speed}, 2000));
    for (int tick = 0; tick < 60; ++tick) {
      bodies.step(1);
      const granular::Vec3 p = world->body_pose(id).position;
      INFO("thrown towards (" << d.x << ", " << d.y << ", " << d.z << "), tick " << tick << ": centre (" << p.x << ", "
                              << p.y << ", " << p.z << ")");
      // Its centre keeps its radius (4 cells, less a tenth of a cell of contact slop) from every face.
      REQUIRE(p.x >= 3.9);
      REQUIRE(p.x <= kN - 3.9);
      REQUIRE(p.y >= 3.9);
      REQUIRE(p.y <= kN - 3.9);
      REQUIRE(p.z >= 3.9);
      REQUIRE(p.z <= kN - 3.9);
    }
  }
}

TEST_CASE("sandbox bodies: a light ball floats in the sand, a heavy one sinks to the floor") {
  auto world = sand_bed();
  SandboxBodies bodies(*world);
  const granular::BodyId cork = bodies.add(ball({14, 24, 30}, {0, 0, -2}, 300));
  const granular::BodyId steel = bodies.add(ball({34, 24, 30}, {0, 0, -2}, 7800));
  bodies.step(200);
  const double cork_z = world->body_pose(cork).position.z, steel_z = world->body_pose(steel).position.z;
  MESSAGE("cork ball centre z " << cork_z << ", steel ball centre z " << steel_z << " (bed top 16, radius 4)");
  CHECK(cork_z > 16);        // most of it above the bed's surface (Archimedes: 19% below)
  CHECK(steel_z < 4 + 1.5);  // on the floor
  CHECK(steel_z > 4 - 0.5);  // but not through it
  bool landed = false, rested = false;
  for (const std::string& line : bodies.take_lines()) {
    landed = landed || line.find("landed in granular") != std::string::npos;
    rested = rested || line.find("at rest") != std::string::npos;
  }
  CHECK(landed);
  CHECK(rested);
}

TEST_CASE("sandbox bodies: past the sandbox's most, a throw is refused with a clear error") {
  auto world = sand_bed();
  SandboxBodies bodies(*world);
  for (std::size_t i = 0; i < kMaxSandboxBodies; ++i)
    bodies.add(ball({6.0 + 9 * double(i % 4), 6.0 + 9 * double(i / 4), 40}, {}, 800, 3));
  CHECK(bodies.count() == kMaxSandboxBodies);
  CHECK_THROWS_WITH_AS(bodies.add(ball({24, 24, 30}, {})), doctest::Contains("the sandbox's most"),
                       granular::StateError);
  CHECK(bodies.count() == kMaxSandboxBodies);
  bodies.step(2);  // still steps
  CHECK(world->tick() == 2);
}

TEST_CASE("sandbox bodies: after an undo, a redo and a restore, Bullet holds exactly the World's bodies") {
  auto world = sand_bed();
  SandboxBodies bodies(*world);
  granular::StrokeHistory history(*world);
  world->step(2);
  history.begin_stroke();
  const granular::BodyDef thrown = ball({24, 24, 40}, {0.5, 0, 0});
  const granular::BodyId id = bodies.add(thrown);
  history.end_stroke();
  bodies.step(20);
  const granular::WorldSnapshot landed = world->capture();
  const granular::BodyPose pose_landed = world->body_pose(id);
  CHECK(pose_landed.position.z < 30);

  REQUIRE(history.undo());
  const BodiesSynced undone = bodies.sync();
  CHECK(undone.removed == 1);
  CHECK(undone.added == 0);
  CHECK(bodies.count() == 0);
  bodies.step(1);  // no rigid body left: the world steps alone
  CHECK(world->tick() == 3);

  // Redo needs the world unchanged since the undo: undo again from a fresh stroke.
  history.begin_stroke();
  const granular::BodyId again = bodies.add(thrown);
  history.end_stroke();
  bodies.step(5);
  REQUIRE(history.undo());
  CHECK(bodies.sync().removed == 1);
  REQUIRE(history.redo());  // sync changed nothing in the World: the redo is still there
  const BodiesSynced redone = bodies.sync();
  CHECK(redone.added == 1);
  CHECK(redone.removed == 0);
  REQUIRE(world->body_ids() == std::vector<granular::BodyId>{again});
  CHECK(world->body_pose(again).position.z == doctest::Approx(40));
  bodies.step(10);
  CHECK(world->body_pose(again).position.z < 40);  // Bullet moves the body the redo brought back

  // A snapshot of another moment: its body comes back into Bullet at its pose and velocity.
  world->restore(landed);
  const BodiesSynced restored = bodies.sync();
  CHECK(restored.removed == restored.added);  // both 0 when the redo's body took the same handle back
  REQUIRE(world->body_ids() == std::vector<granular::BodyId>{id});
  CHECK(bodies.count() == 1);
  CHECK(world->body_pose(id).position.z == doctest::Approx(pose_landed.position.z));
  bodies.step(5);
  CHECK(world->body_pose(id).position.z == doctest::Approx(pose_landed.position.z).epsilon(0.2));
}
