#include "bodies/sandbox_bodies.hpp"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "bodies/body_throw.hpp"
#include "bodies/body_watch.hpp"
#include "granular/bullet_body.hpp"
#include "granular/bullet_coupling.hpp"
#include "granular/errors.hpp"
#include "granular/time_scale.hpp"

namespace viewer {

namespace {

constexpr double kGravity = 9.81;     // m/s^2
constexpr btScalar kFriction = 0.8f;  // bodies against the grid's faces and static cells
constexpr int kStaticMargin = 4;      // cells around a body (and its path over the tick) that collide

}  // namespace

/// Bullet's world, the grid's faces, the coupling and the rigid bodies.
struct SandboxBodies::Physics {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld dynamics{&dispatcher, &broadphase, &solver, &configuration};
  std::array<std::unique_ptr<btStaticPlaneShape>, 6> face_shapes;
  std::array<std::unique_ptr<btCollisionObject>, 6> faces;
  std::unique_ptr<granular::BulletCoupling> coupling;
  std::vector<granular::BulletBody> bodies;
  BodyWatch watch;
  std::vector<std::string> lines;
  double cell_metres;
  double tick_seconds;

  Physics(granular::World& world, double cell, double tick)
      : watch(world.rules().materials, tick, cell), cell_metres(cell), tick_seconds(tick) {}

  /// Adds `body`'s rigid body to Bullet, with continuous collision for its size, and keeps it.
  btRigidBody& keep(granular::BulletBody body, double half_size_cells) {
    btRigidBody& rigid = *body.rigid;
    const btScalar half = btScalar(half_size_cells * cell_metres);
    rigid.setFriction(kFriction);
    // Continuous collision once a substep moves it more than half its size: swept as its inscribed
    // sphere (a ball itself, a box within its faces), so no throw passes a face or a thin wall.
    rigid.setCcdMotionThreshold(half * 0.5f);
    rigid.setCcdSweptSphereRadius(half);
    dynamics.addRigidBody(&rigid);
    bodies.push_back(std::move(body));
    return rigid;
  }

  /// Removes `rigid` from Bullet and frees it.
  void drop(btRigidBody* rigid) {
    dynamics.removeRigidBody(rigid);
    std::erase_if(bodies, [&](const granular::BulletBody& b) { return b.rigid.get() == rigid; });
  }
};

namespace {

/// The smallest half size of `def`'s shape, in cells: what continuous collision sweeps.
double smallest_half(const granular::BodyDef& def) {
  if (def.shape == granular::BodyShape::Box)
    return std::min({def.half_extents.x, def.half_extents.y, def.half_extents.z});
  return def.radius;
}

}  // namespace

SandboxBodies::SandboxBodies(granular::World& world)
    : world_(world),
      physics_(std::make_unique<Physics>(world, world.def().cell_metres,
                                         granular::tick_seconds(world.rules(), world.def().cell_metres))) {
  Physics& p = *physics_;
  p.dynamics.setGravity(btVector3(0, 0, btScalar(-kGravity)));
  // Bullet's default lets a sweep pass 4 cm (8 cells) before continuous collision stops it: a tolerance
  // for bodies a metre across. Here it is half a cell.
  p.dynamics.getDispatchInfo().m_allowedCcdPenetration = btScalar(0.5 * p.cell_metres);
  granular::BulletCouplingDef def;
  def.static_margin = kStaticMargin;
  p.coupling = std::make_unique<granular::BulletCoupling>(world, p.dynamics, def);
  // The grid's six faces, each a static half-space whose normal points into the grid, so that no
  // body leaves it whatever its speed.
  const granular::Int3 n = world.size();
  const double m = p.cell_metres;
  const std::array<std::pair<btVector3, double>, 6> planes{{{btVector3(1, 0, 0), 0},
                                                            {btVector3(-1, 0, 0), -n.x * m},
                                                            {btVector3(0, 1, 0), 0},
                                                            {btVector3(0, -1, 0), -n.y * m},
                                                            {btVector3(0, 0, 1), 0},
                                                            {btVector3(0, 0, -1), -n.z * m}}};
  for (std::size_t i = 0; i < planes.size(); ++i) {
    p.face_shapes[i] = std::make_unique<btStaticPlaneShape>(planes[i].first, btScalar(planes[i].second));
    p.faces[i] = std::make_unique<btCollisionObject>();
    p.faces[i]->setCollisionShape(p.face_shapes[i].get());
    p.faces[i]->setCollisionFlags(p.faces[i]->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
    p.faces[i]->setFriction(kFriction);
    p.dynamics.addCollisionObject(p.faces[i].get());
  }
}

SandboxBodies::~SandboxBodies() {
  Physics& p = *physics_;
  for (granular::BulletBody& body : p.bodies) p.dynamics.removeRigidBody(body.rigid.get());
  for (auto& face : p.faces) p.dynamics.removeCollisionObject(face.get());
  p.coupling.reset();  // takes its static cells out of Bullet before the dynamics world goes
}

granular::BodyId SandboxBodies::add(const granular::BodyDef& def) {
  Physics& p = *physics_;
  if (count() >= kMaxSandboxBodies)
    throw granular::StateError("there are " + std::to_string(count()) + " bodies already, the sandbox's most");
  granular::BulletBody body = granular::make_bullet_body(def, p.cell_metres, p.tick_seconds);
  btRigidBody& rigid = p.keep(std::move(body), smallest_half(def));
  granular::BodyId id = 0;
  try {
    id = p.coupling->add(rigid);
  } catch (...) {
    p.drop(&rigid);
    throw;
  }
  p.watch.follow(id, world_.tick(), def.pose.position, def.pose.velocity);
  return id;
}

void SandboxBodies::step(int ticks) {
  Physics& p = *physics_;
  if (p.bodies.empty()) {
    world_.step(ticks);
    return;
  }
  std::vector<BodyReading> readings;
  for (int t = 0; t < ticks; ++t) {
    // Where each body is written this tick: Bullet's pose now, which the coupling hands the World.
    readings.clear();
    for (const granular::BulletBody& body : p.bodies) {
      btVector3 lo, hi;
      body.rigid->getAabb(lo, hi);
      const btVector3 at = body.rigid->getWorldTransform().getOrigin();
      BodyReading reading;
      reading.id = p.coupling->body_of(*body.rigid);
      reading.position = {at.x() / p.cell_metres, at.y() / p.cell_metres, at.z() / p.cell_metres};
      reading.bottom = lo.z() / p.cell_metres;
      readings.push_back(reading);
    }
    const std::uint64_t tick = world_.tick();
    p.coupling->step();
    for (BodyReading& reading : readings) reading.sand = &world_.body_sand(reading.id);
    for (std::string& line : p.watch.observe(tick, readings)) p.lines.push_back(std::move(line));
  }
}

BodiesSynced SandboxBodies::sync() {
  Physics& p = *physics_;
  const granular::CouplingSync found = p.coupling->sync();
  BodiesSynced result;
  for (btRigidBody* rigid : found.uncoupled) p.drop(rigid);
  result.removed = found.uncoupled.size();
  for (const granular::BodyId id : found.unmatched) {
    const granular::BodyDef def = world_.body_def(id);
    btRigidBody& rigid = p.keep(granular::make_bullet_body(def, p.cell_metres, p.tick_seconds), smallest_half(def));
    p.coupling->couple(rigid, id);
  }
  result.added = found.unmatched.size();
  // Every body starts its landing and rest anew from where the World has it now.
  const std::vector<granular::BodyId> ids = world_.body_ids();
  p.watch.keep_only(ids);
  for (const granular::BodyId id : ids) {
    const granular::BodyPose pose = world_.body_pose(id);
    p.watch.follow(id, world_.tick(), pose.position, pose.velocity, false);
  }
  return result;
}

std::size_t SandboxBodies::count() const { return world_.body_ids().size(); }

std::vector<std::string> SandboxBodies::take_lines() { return std::exchange(physics_->lines, {}); }

}  // namespace viewer
