#pragma once
/// @file body_scene.hpp
/// The scene the bodies' conservation and CPU = CUDA tests share: a bed of sand with gravel in it
/// under water, gas above, and ten bodies of every shape wandering through it.

#include <random>
#include <vector>

#include "granular/body.hpp"
#include "granular/world.hpp"

namespace granular::test {

/// Bodies wandering through a bed of a 48 x 48 x 40 world (or larger): the same for every seed.
class WanderingBodies {
 public:
  /// Paints the bed into `w` and adds the ten bodies.
  explicit WanderingBodies(World& w) : world_(w) {
    w.paint(Box{{0, 0, 0}, {48, 48, 12}}, Material::Granular);
    w.paint(Box{{16, 16, 4}, {32, 32, 10}}, Material::Gravel);
    w.paint(Box{{0, 0, 12}, {48, 48, 20}}, Material::Liquid);
    w.pour({24, 24, 32}, 5, Material::Gas, 150);
    for (int i = 0; i < 10; ++i) {
      BodyDef def;
      def.shape = BodyShape(i % 3);
      def.half_extents = {2 + 2 * unit(), 2 + 2 * unit(), 2 + 2 * unit()};
      def.radius = 2 + 2 * unit();
      def.half_length = 1 + 2 * unit();
      def.pose.position = {8 + 32 * unit(), 8 + 32 * unit(), 6 + 24 * unit()};
      def.pose.orientation = {unit(), unit(), unit(), unit()};
      def.pose.angular_velocity = {0.05 * unit(), 0.05 * unit(), 0.05 * unit()};
      ids.push_back(w.add_body(def));
    }
  }

  /// Steps one tick; every 25th tick first gives each body a new heading, turned back at the walls.
  void tick() {
    if (ticks_++ % 25 == 0)
      for (const BodyId id : ids) {
        BodyPose pose = world_.body_pose(id);
        Vec3 v{unit() - 0.5, unit() - 0.5, unit() - 0.5};
        if (pose.position.x < 10) v.x = 0.5;
        if (pose.position.x > 38) v.x = -0.5;
        if (pose.position.y < 10) v.y = 0.5;
        if (pose.position.y > 38) v.y = -0.5;
        if (pose.position.z < 8) v.z = 0.5;
        if (pose.position.z > 30) v.z = -0.5;
        pose.velocity = v;
        world_.set_body_pose(id, pose);
      }
    world_.step(1);
  }

  std::vector<BodyId> ids;  ///< the bodies, in the order added

 private:
  double unit() { return std::uniform_real_distribution<double>(0, 1)(rng_); }

  World& world_;
  std::mt19937_64 rng_{11};
  int ticks_ = 0;
};

}  // namespace granular::test
