#include "granular/bullet_coupling.hpp"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "granular/bullet_body.hpp"
#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/rule_set.hpp"
#include "granular/time_scale.hpp"

namespace granular {

namespace {

/// A run of static cells along x: cells [x0, x1) of row (y, z); coordinates may lie outside the grid.
struct StaticRun {
  int z, y, x0, x1;
  friend bool operator==(const StaticRun&, const StaticRun&) = default;
};

/// Packs a cell that may lie up to 2^19 cells outside the grid into a sortable key (z, y, x).
std::uint64_t pack(int x, int y, int z) {
  constexpr std::int64_t kOffset = 1 << 19;
  return (std::uint64_t(z + kOffset) << 42) | (std::uint64_t(y + kOffset) << 21) | std::uint64_t(x + kOffset);
}
Int3 unpack(std::uint64_t k) {
  constexpr std::int64_t kOffset = 1 << 19;
  constexpr std::uint64_t kMask = (std::uint64_t(1) << 21) - 1;
  return {int(std::int64_t(k & kMask) - kOffset), int(std::int64_t((k >> 21) & kMask) - kOffset),
          int(std::int64_t(k >> 42) - kOffset)};
}

}  // namespace

BulletCoupling::BulletCoupling(World& world, btDiscreteDynamicsWorld& dynamics, const BulletCouplingDef& def)
    : world_(world),
      dynamics_(dynamics),
      def_(def),
      cell_m_(world.def().cell_metres),
      tick_s_(tick_seconds(world.rules(), world.def().cell_metres)) {
  if (def.substeps < 1 || def.substeps > 64)
    throw InvalidArgument("BulletCouplingDef::substeps = " + std::to_string(def.substeps) + "; use 1..64");
  if (def.static_margin < 1 || def.static_margin > 32)
    throw InvalidArgument("BulletCouplingDef::static_margin = " + std::to_string(def.static_margin) + "; use 1..32");
}

BulletCoupling::~BulletCoupling() {
  if (statics_) dynamics_.removeCollisionObject(statics_.get());
}

BodyId BulletCoupling::add(btRigidBody& rigid) {
  for (const Coupled& c : coupled_)
    if (c.rigid == &rigid) throw InvalidArgument("BulletCoupling::add: this rigid body is coupled already");
  if (rigid.getInvMass() == 0)
    throw InvalidArgument("BulletCoupling::add: a static or kinematic rigid body (mass 0) is not moved by the sand");
  const BodyDef def = body_def_of(*rigid.getCollisionShape(), 1.0 / rigid.getInvMass(), cell_m_);
  const BodyId id = world_.add_body(def);
  coupled_.push_back({&rigid, id});
  write_poses();
  return id;
}

void BulletCoupling::remove(btRigidBody& rigid) {
  const auto it = std::find_if(coupled_.begin(), coupled_.end(), [&](const Coupled& c) { return c.rigid == &rigid; });
  if (it == coupled_.end()) throw InvalidArgument("BulletCoupling::remove: this rigid body is not coupled");
  world_.remove_body(it->body);
  coupled_.erase(it);
}

BodyId BulletCoupling::body_of(const btRigidBody& rigid) const {
  for (const Coupled& c : coupled_)
    if (c.rigid == &rigid) return c.body;
  throw InvalidArgument("BulletCoupling::body_of: this rigid body is not coupled");
}

void BulletCoupling::couple(btRigidBody& rigid, BodyId body) {
  for (const Coupled& c : coupled_) {
    if (c.rigid == &rigid) throw InvalidArgument("BulletCoupling::couple: this rigid body is coupled already");
    if (c.body == body)
      throw InvalidArgument("BulletCoupling::couple: body " + std::to_string(body) + " has a rigid body already");
  }
  if (rigid.getInvMass() == 0)
    throw InvalidArgument("BulletCoupling::couple: a static or kinematic rigid body (mass 0) is not moved by the sand");
  if (!matches(rigid, world_.body_def(body)))  // body_def throws InvalidArgument for an unknown body
    throw InvalidArgument("BulletCoupling::couple: the rigid body's shape or mass is not body " + std::to_string(body) +
                          "'s (build it with make_bullet_body(world.body_def(id), ...))");
  coupled_.push_back({&rigid, body});
  read_pose(rigid, body);
}

CouplingSync BulletCoupling::sync() {
  CouplingSync result;
  std::vector<BodyId> ids = world_.body_ids();
  std::sort(ids.begin(), ids.end());
  std::vector<Coupled> kept;
  for (const Coupled& c : coupled_) {
    // A handle an undo or a restore gave back may name another body now: that one needs a rigid body of its own.
    if (std::binary_search(ids.begin(), ids.end(), c.body) && matches(*c.rigid, world_.body_def(c.body))) {
      kept.push_back(c);
      read_pose(*c.rigid, c.body);
    } else {
      result.uncoupled.push_back(c.rigid);
    }
  }
  coupled_ = std::move(kept);
  for (const BodyId id : ids)
    if (std::none_of(coupled_.begin(), coupled_.end(), [&](const Coupled& c) { return c.body == id; }))
      result.unmatched.push_back(id);
  return result;
}

bool BulletCoupling::matches(const btRigidBody& rigid, const BodyDef& want) const {
  const BodyDef have = body_def_of(*rigid.getCollisionShape(), 1.0 / rigid.getInvMass(), cell_m_);
  auto near = [](double a, double b) { return std::abs(a - b) <= 1e-4 * std::max(std::abs(a), std::abs(b)); };
  if (have.shape != want.shape || !near(have.density, want.density)) return false;
  switch (want.shape) {
    case BodyShape::Box:
      return near(have.half_extents.x, want.half_extents.x) && near(have.half_extents.y, want.half_extents.y) &&
             near(have.half_extents.z, want.half_extents.z);
    case BodyShape::Sphere: return near(have.radius, want.radius);
    case BodyShape::Capsule: return near(have.radius, want.radius) && near(have.half_length, want.half_length);
  }
  return false;
}

std::vector<btRigidBody*> BulletCoupling::rigid_bodies() const {
  std::vector<btRigidBody*> result;
  for (const Coupled& c : coupled_) result.push_back(c.rigid);
  return result;
}

void BulletCoupling::read_pose(btRigidBody& rigid, BodyId body) const {
  const BodyPose pose = world_.body_pose(body);
  const double per_second = cell_m_ / tick_s_;
  btTransform at;
  at.setOrigin(btVector3(btScalar(pose.position.x * cell_m_), btScalar(pose.position.y * cell_m_),
                         btScalar(pose.position.z * cell_m_)));
  at.setRotation(btQuaternion(btScalar(pose.orientation.x), btScalar(pose.orientation.y), btScalar(pose.orientation.z),
                              btScalar(pose.orientation.w)));
  rigid.setWorldTransform(at);
  rigid.setInterpolationWorldTransform(at);
  if (rigid.getMotionState()) rigid.getMotionState()->setWorldTransform(at);
  rigid.setLinearVelocity(btVector3(btScalar(pose.velocity.x * per_second), btScalar(pose.velocity.y * per_second),
                                    btScalar(pose.velocity.z * per_second)));
  rigid.setAngularVelocity(btVector3(btScalar(pose.angular_velocity.x / tick_s_),
                                     btScalar(pose.angular_velocity.y / tick_s_),
                                     btScalar(pose.angular_velocity.z / tick_s_)));
  rigid.setInterpolationLinearVelocity(rigid.getLinearVelocity());
  rigid.setInterpolationAngularVelocity(rigid.getAngularVelocity());
  rigid.clearForces();
  rigid.activate(true);
}

void BulletCoupling::write_poses() {
  const double to_cells = 1.0 / cell_m_, per_tick = tick_s_ / cell_m_;
  for (const Coupled& c : coupled_) {
    const btTransform& t = c.rigid->getWorldTransform();
    const btVector3 p = t.getOrigin();
    const btQuaternion q = t.getRotation();
    const btVector3 v = c.rigid->getLinearVelocity(), w = c.rigid->getAngularVelocity();
    BodyPose pose;
    pose.position = {p.x() * to_cells, p.y() * to_cells, p.z() * to_cells};
    pose.orientation = {q.w(), q.x(), q.y(), q.z()};
    pose.velocity = {v.x() * per_tick, v.y() * per_tick, v.z() * per_tick};
    pose.angular_velocity = {w.x() * tick_s_, w.y() * tick_s_, w.z() * tick_s_};
    world_.set_body_pose(c.body, pose);
  }
}

void BulletCoupling::apply_forces() {
  for (const Coupled& c : coupled_) {
    const BodySand& sand = world_.body_sand(c.body);
    c.rigid->activate(true);
    c.rigid->applyCentralForce(btVector3(btScalar(sand.force.x), btScalar(sand.force.y), btScalar(sand.force.z)));
    c.rigid->applyTorque(btVector3(btScalar(sand.torque.x), btScalar(sand.torque.y), btScalar(sand.torque.z)));
  }
}

void BulletCoupling::rebuild_statics() {
  // The static cells with a non-static neighbour around each body (and the cells past the grid,
  // which are static to the rules too), as one sorted set.
  const Int3 n = world_.size();
  const MaterialTable& materials = world_.rules().materials;
  const std::uint8_t body = to_cell(world_.def().body_material);
  // The cells the coupled bodies hold (Bullet has those bodies); every other cell of the body
  // material (a game's structure, a body it moves itself) is static.
  std::vector<std::uint64_t> held;
  for (const Coupled& c : coupled_) {
    const std::span<const std::uint64_t> own = world_.body_cells(c.body);
    held.insert(held.end(), own.begin(), own.end());
  }
  std::sort(held.begin(), held.end());
  std::vector<std::uint64_t> cells;
  std::vector<std::uint8_t> region;
  for (const Coupled& c : coupled_) {
    btVector3 lo, hi;
    c.rigid->getAabb(lo, hi);
    // The box the body sweeps over the coming tick (up to 256 cells of it), so that a fast body
    // meets the static cells in its path.
    btVector3 path = c.rigid->getLinearVelocity() * btScalar(tick_s_);
    const btScalar longest = btScalar(256 * cell_m_);
    if (path.length() > longest) path *= longest / path.length();
    lo.setMin(lo + path);
    hi.setMax(hi + path);
    const int m = def_.static_margin;
    const Box want{{int(std::floor(lo.x() / cell_m_)) - m, int(std::floor(lo.y() / cell_m_)) - m,
                    int(std::floor(lo.z() / cell_m_)) - m},
                   {int(std::floor(hi.x() / cell_m_)) + m + 1, int(std::floor(hi.y() / cell_m_)) + m + 1,
                    int(std::floor(hi.z() / cell_m_)) + m + 1}};
    const Box inside = intersect(want, Box{{0, 0, 0}, n});
    // An AABB larger than any body World takes (kMaxBodyHalfSize) is not one of its bodies' shapes.
    if (want.extent().x > 1024 || want.extent().y > 1024 || want.extent().z > 1024) continue;
    const Int3 e = inside.extent();
    if (!inside.empty()) {
      region.resize(std::size_t(inside.volume()));
      world_.read_region(inside, region);
    }
    auto is_static = [&](int x, int y, int z) {
      if (x < 0 || y < 0 || z < 0 || x >= n.x || y >= n.y || z >= n.z) return true;
      if (x < inside.min.x || y < inside.min.y || z < inside.min.z || x >= inside.max.x || y >= inside.max.y ||
          z >= inside.max.z)
        return true;  // outside what was read: counts as static, so the region's edge makes no face
      const std::uint8_t m8 =
          region[(std::size_t(z - inside.min.z) * std::size_t(e.y) + std::size_t(y - inside.min.y)) * std::size_t(e.x) +
                 std::size_t(x - inside.min.x)];
      if (materials[m8].behaviour != Behaviour::Static) return false;
      return m8 != body ||
             !std::binary_search(held.begin(), held.end(),
                                 std::uint64_t(x) + std::uint64_t(n.x) * (std::uint64_t(y) + std::uint64_t(n.y) * std::uint64_t(z)));
    };
    for (int z = want.min.z; z < want.max.z; ++z)
      for (int y = want.min.y; y < want.max.y; ++y)
        for (int x = want.min.x; x < want.max.x; ++x) {
          if (!is_static(x, y, z)) continue;
          const bool surface = !is_static(x + 1, y, z) || !is_static(x - 1, y, z) || !is_static(x, y + 1, z) ||
                               !is_static(x, y - 1, z) || !is_static(x, y, z + 1) || !is_static(x, y, z - 1);
          if (surface) cells.push_back(pack(x, y, z));
        }
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<StaticRun> runs;
  for (const std::uint64_t k : cells) {
    const Int3 c = unpack(k);
    if (!runs.empty() && runs.back().z == c.z && runs.back().y == c.y && runs.back().x1 == c.x)
      ++runs.back().x1;
    else
      runs.push_back({c.z, c.y, c.x, c.x + 1});
  }
  std::uint64_t key = runs.size();
  for (const StaticRun& r : runs) key = mix64(key ^ pack(r.x0, r.y, r.z) ^ (std::uint64_t(std::uint32_t(r.x1)) << 11));
  if (statics_ && key == statics_key_) return;
  statics_key_ = key;
  if (statics_) dynamics_.removeCollisionObject(statics_.get());
  statics_.reset();
  statics_shape_ = std::make_unique<btCompoundShape>(true, int(runs.size()));
  boxes_.clear();
  for (const StaticRun& r : runs) {
    const double half_x = 0.5 * (r.x1 - r.x0) * cell_m_, half = 0.5 * cell_m_;
    boxes_.push_back(std::make_unique<btBoxShape>(btVector3(btScalar(half_x), btScalar(half), btScalar(half))));
    boxes_.back()->setMargin(0);
    btTransform at;
    at.setIdentity();
    at.setOrigin(btVector3(btScalar(0.5 * (r.x0 + r.x1) * cell_m_), btScalar((r.y + 0.5) * cell_m_),
                           btScalar((r.z + 0.5) * cell_m_)));
    statics_shape_->addChildShape(at, boxes_.back().get());
  }
  statics_ = std::make_unique<btCollisionObject>();
  statics_->setCollisionShape(statics_shape_.get());
  statics_->setCollisionFlags(statics_->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
  statics_->setFriction(0.8);
  dynamics_.addCollisionObject(statics_.get());
}

void BulletCoupling::step() {
  write_poses();
  world_.step(1);
  apply_forces();
  rebuild_statics();
  dynamics_.stepSimulation(btScalar(tick_s_), def_.substeps, btScalar(tick_s_ / def_.substeps));
  write_poses();  // between steps the World holds Bullet's poses: what capture() and an undo keep
}

std::size_t BulletCoupling::static_boxes() const { return boxes_.size(); }

}  // namespace granular
