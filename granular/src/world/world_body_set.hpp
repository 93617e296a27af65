#pragma once
/// @file world_body_set.hpp
/// The bodies a World holds (World::Bodies): each body's definition, pose, the cells it holds and its
/// last report, and the scratch of writing them into the grid.

#include <cstdint>
#include <vector>

#include "bodies/body_forces.hpp"
#include "bodies/body_stamp.hpp"
#include "granular/body.hpp"
#include "granular/world.hpp"

namespace granular {

/// One body of the world.
struct BodyRecord {
  BodyId id = 0;
  BodyDef def;
  BodyPose pose;                           ///< where it is written at the next tick
  std::vector<std::uint64_t> owned;        ///< grid indices (ascending) of the cells it holds
  BodySand sand;                           ///< the last tick's report
  double mass = 0;                         ///< kg
  double moment = 0;                       ///< kg m^2, of a ball of the same volume and mass
  Box region;                              ///< the region of its last stamp
  std::vector<std::uint8_t> region_bytes;  ///< that region's cell bytes after the stamp (empty: not kept)
  std::uint64_t version = 0;               ///< World::change_version() after the stamp
};

/// The bodies of a World.
struct World::Bodies {
  std::vector<BodyRecord> list;      ///< in the order they were added
  BodyId next = 1;                   ///< the next handle
  std::vector<std::uint64_t> shape;  ///< scratch: the cells of a body's shape this tick
  StampScratch stamp;
  ForceScratch forces;
};

}  // namespace granular
