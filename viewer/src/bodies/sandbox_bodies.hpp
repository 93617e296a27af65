#pragma once
/// @file sandbox_bodies.hpp
/// The bodies the sandbox throws, moved by Bullet (built only with granular::bullet): a Bullet
/// dynamics world (z up, metres) whose grid faces are six static planes, a BulletCoupling with the
/// session's World, the rigid bodies, and the world's ticks run a tick at a time so that Bullet and
/// the World stay in lockstep. After an undo, a redo or a load it brings Bullet back in line with
/// the World's bodies (sync).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "granular/body.hpp"
#include "granular/world.hpp"

namespace viewer {

/// What SandboxBodies::sync changed in Bullet.
struct BodiesSynced {
  std::size_t removed = 0;  ///< rigid bodies dropped: their World body is gone
  std::size_t added = 0;    ///< rigid bodies made for World bodies Bullet did not know
};

/// The sandbox's bodies in Bullet, beside one World (which must outlive this).
class SandboxBodies {
 public:
  /// Bullet for `world`: gravity 9.81 m/s^2 down, the grid's six faces as static planes, nothing
  /// coupled yet (sync() couples the bodies `world` holds already).
  explicit SandboxBodies(granular::World& world);
  /// Removes every rigid body and plane from Bullet; the World's bodies stay.
  ~SandboxBodies();
  SandboxBodies(const SandboxBodies&) = delete;
  SandboxBodies& operator=(const SandboxBodies&) = delete;

  /// Adds a World body of `def` (its shape, size, density and pose: position in cells, velocity in
  /// cells per tick) and a rigid body that moves it, and follows it (landing and rest lines). Throws
  /// granular::StateError when there are kMaxSandboxBodies already (body_throw.hpp), and
  /// granular::InvalidArgument for a def World::add_body refuses; nothing changes then.
  granular::BodyId add(const granular::BodyDef& def);

  /// Runs `ticks` world ticks: one BulletCoupling::step each while there are bodies (the World writes
  /// the bodies at Bullet's poses, steps, and Bullet steps the tick's length under the sand's
  /// forces), else World::step(ticks) at once.
  void step(int ticks);

  /// After the World's bodies changed without Bullet (an undo, a redo, a loaded snapshot): drops the
  /// rigid bodies whose World body is gone, makes one for each World body Bullet does not know (from
  /// World::body_def: shape, size, density, pose and velocity), and moves the others to their World
  /// body's pose. Changes nothing in the World.
  BodiesSynced sync();

  /// The bodies there are (World::body_ids().size()).
  std::size_t count() const;

  /// The lines since the last call about bodies that landed or came to rest (body_watch.hpp).
  std::vector<std::string> take_lines();

 private:
  struct Physics;
  granular::World& world_;
  std::unique_ptr<Physics> physics_;
};

}  // namespace viewer
