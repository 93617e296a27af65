#include "granular/bullet_body.hpp"

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <string>

#include "granular/errors.hpp"

namespace granular {

namespace {

/// Throws InvalidArgument naming `what` unless `value` is finite and > 0.
void check_positive(double value, const char* what) {
  if (!std::isfinite(value) || value <= 0)
    throw InvalidArgument(std::string(what) + " = " + std::to_string(value) + "; must be finite and > 0");
}

}  // namespace

std::unique_ptr<btCollisionShape> bullet_shape(const BodyDef& def, double cell_metres) {
  check_positive(cell_metres, "bullet_shape: cell_metres");
  const double m = cell_metres;
  switch (def.shape) {
    case BodyShape::Box:
      check_positive(def.half_extents.x, "bullet_shape: half_extents.x");
      check_positive(def.half_extents.y, "bullet_shape: half_extents.y");
      check_positive(def.half_extents.z, "bullet_shape: half_extents.z");
      return std::make_unique<btBoxShape>(btVector3(btScalar(def.half_extents.x * m), btScalar(def.half_extents.y * m),
                                                    btScalar(def.half_extents.z * m)));
    case BodyShape::Sphere:
      check_positive(def.radius, "bullet_shape: radius");
      return std::make_unique<btSphereShape>(btScalar(def.radius * m));
    case BodyShape::Capsule:
      check_positive(def.radius, "bullet_shape: radius");
      if (!std::isfinite(def.half_length) || def.half_length < 0)
        throw InvalidArgument("bullet_shape: half_length = " + std::to_string(def.half_length) +
                              "; must be finite and >= 0");
      return std::make_unique<btCapsuleShapeZ>(btScalar(def.radius * m), btScalar(2 * def.half_length * m));
  }
  throw InvalidArgument("bullet_shape: shape " + std::to_string(int(def.shape)) + " is not a box, sphere or capsule");
}

double body_mass(const BodyDef& def, double cell_metres) {
  return def.density * shape_volume(def) * cell_metres * cell_metres * cell_metres;
}

BodyDef body_def_of(const btCollisionShape& shape, double mass, double cell_metres) {
  check_positive(mass, "body_def_of: mass");
  check_positive(cell_metres, "body_def_of: cell_metres");
  BodyDef def;
  const double to_cells = 1.0 / cell_metres;
  switch (shape.getShapeType()) {
    case BOX_SHAPE_PROXYTYPE: {
      const btVector3 h = static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin();
      def.shape = BodyShape::Box;
      def.half_extents = {h.x() * to_cells, h.y() * to_cells, h.z() * to_cells};
      break;
    }
    case SPHERE_SHAPE_PROXYTYPE:
      def.shape = BodyShape::Sphere;
      def.radius = static_cast<const btSphereShape&>(shape).getRadius() * to_cells;
      break;
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto& capsule = static_cast<const btCapsuleShape&>(shape);
      if (capsule.getUpAxis() != 2) throw InvalidArgument("body_def_of: a capsule must lie along z (btCapsuleShapeZ)");
      def.shape = BodyShape::Capsule;
      def.radius = capsule.getRadius() * to_cells;
      def.half_length = capsule.getHalfHeight() * to_cells;
      break;
    }
    default:
      throw InvalidArgument("body_def_of: collision shape type " + std::to_string(shape.getShapeType()) +
                            " is not a btBoxShape, btSphereShape or btCapsuleShapeZ");
  }
  // The density that gives the World body Bullet's mass.
  def.density = mass / (shape_volume(def) * cell_metres * cell_metres * cell_metres);
  return def;
}

BulletBody::BulletBody() = default;
BulletBody::~BulletBody() {
  rigid.reset();
  motion.reset();
  shape.reset();
}
BulletBody::BulletBody(BulletBody&& other) noexcept = default;
BulletBody& BulletBody::operator=(BulletBody&& other) noexcept {
  rigid = std::move(other.rigid);
  motion = std::move(other.motion);
  shape = std::move(other.shape);
  return *this;
}

BulletBody make_bullet_body(const BodyDef& def, double cell_metres, double tick_seconds) {
  check_positive(tick_seconds, "make_bullet_body: tick_seconds");
  BulletBody body;
  body.shape = bullet_shape(def, cell_metres);
  const btScalar mass = btScalar(body_mass(def, cell_metres));
  btVector3 inertia(0, 0, 0);
  body.shape->calculateLocalInertia(mass, inertia);
  const BodyPose& pose = def.pose;
  btTransform at;
  at.setOrigin(btVector3(btScalar(pose.position.x * cell_metres), btScalar(pose.position.y * cell_metres),
                         btScalar(pose.position.z * cell_metres)));
  at.setRotation(btQuaternion(btScalar(pose.orientation.x), btScalar(pose.orientation.y), btScalar(pose.orientation.z),
                              btScalar(pose.orientation.w)));
  body.motion = std::make_unique<btDefaultMotionState>(at);
  body.rigid = std::make_unique<btRigidBody>(mass, body.motion.get(), body.shape.get(), inertia);
  const double per_second = cell_metres / tick_seconds;
  body.rigid->setLinearVelocity(btVector3(btScalar(pose.velocity.x * per_second),
                                          btScalar(pose.velocity.y * per_second),
                                          btScalar(pose.velocity.z * per_second)));
  body.rigid->setAngularVelocity(btVector3(btScalar(pose.angular_velocity.x / tick_seconds),
                                           btScalar(pose.angular_velocity.y / tick_seconds),
                                           btScalar(pose.angular_velocity.z / tick_seconds)));
  return body;
}

}  // namespace granular
