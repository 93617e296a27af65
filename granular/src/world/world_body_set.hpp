#pragma once
/// @file world_body_set.hpp
/// The bodies a World holds (World::Bodies): each body's definition, pose, the cells it holds and its
/// last report, and the scratch of writing them into the grid.

#include <cstdint>
#include <memory>
#include <vector>

#include "bodies/body_forces.hpp"
#include "bodies/body_stamp.hpp"
#include "granular/body.hpp"
#include "granular/task_system.hpp"
#include "granular/world.hpp"
#include "world/region_edit.hpp"

namespace granular {

/// One body of the world; a task that stamps it writes it, so it starts a cache line of its own.
struct alignas(64) BodyRecord {
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

/// One body's part of a tick's stamp (World::stamp_bodies), kept from tick to tick for its buffers;
/// a cache line of its own, like BodyRecord.
struct alignas(64) BodyStampWork {
  std::vector<std::uint64_t> shape;  ///< the cells of its shape this tick
  Box bounds;                        ///< their bounds (empty: none in the grid)
  Box held;                          ///< the bounds of the cells it holds (empty: none)
  Box region;                        ///< the cells it reads and writes this tick (empty: none)
  bool at_rest = false;              ///< it holds its shape in a region nothing changed since its last stamp
  bool stamped = false;              ///< its group was stamped this tick: edit holds its region as the group left it
  std::size_t group = 0;             ///< the first body of its group (bodies whose regions overlap)
  RegionEdit edit;                   ///< its region's cells and the bricks its stamp wrote
  std::size_t changes = 0;           ///< cells its shape gains and loses this tick
  double ms_per_change = -1;  ///< host time its last stamp with changes took per change (-1: none yet), to schedule by
};

/// The bodies of a World.
struct World::Bodies {
  std::vector<BodyRecord> list;       ///< in the order they were added
  BodyId next = 1;                    ///< the next handle
  std::vector<BodyStampWork> work;    ///< per body of `list`, this tick's stamp
  std::vector<StampScratch> stamp;    ///< per task of the stamp
  std::vector<ForceScratch> forces;   ///< per task of the forces
  std::shared_ptr<TaskSystem> tasks;  ///< the threads the groups are stamped on (null until the first stamp)
  std::vector<std::uint8_t> packed;   ///< the moving regions' bytes, one after another, as read and as written,
                                      ///< where the backend has no transfer buffer
};

}  // namespace granular
