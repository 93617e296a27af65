#pragma once
/// @file body_watch.hpp
/// What the sandbox says about each body it moves, tick by tick: the tick it lands (first touches a
/// grain, a liquid or a static cell, the floor included), with the time a free fall from where it was
/// thrown takes to that height beside it, and the tick it comes to rest, each once, as a line on
/// stdout. Pure logic on the World's reports (BodySand), no Bullet.

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "granular/body.hpp"
#include "granular/geometry.hpp"
#include "granular/rule_set.hpp"

namespace viewer {

/// Ticks a body's centre must stay within kRestCells of where it is to be at rest.
inline constexpr int kRestTicks = 30;
/// How far a body at rest may move over kRestTicks, in cells (a body floating in water moves within
/// half a cell: docs/design/bodies.md).
inline constexpr double kRestCells = 0.75;
/// How far a body must move from where it came to rest, in cells, before it can come to rest again
/// (and be reported again): a body settling deeper by a cell or two is still the same rest.
inline constexpr double kMovedCells = 3;

/// One body in one tick: where it was written at the start of the tick and what the sand reported.
struct BodyReading {
  granular::BodyId id = 0;                   ///< the World's handle
  granular::Vec3 position;                   ///< its centre at the tick's start, cells
  double bottom = 0;                         ///< its lowest point then, cells above the floor
  const granular::BodySand* sand = nullptr;  ///< World::body_sand after the tick (not null)
};

/// Follows the bodies of one World and says when each lands and comes to rest.
class BodyWatch {
 public:
  /// Watches bodies in a world of `materials`, with ticks of `tick_seconds` and cells of
  /// `cell_metres` (for the free fall's time); throws std::invalid_argument for a unit that is not
  /// finite and > 0.
  BodyWatch(const granular::MaterialTable& materials, double tick_seconds, double cell_metres);

  /// Starts following body `id`, which leaves `position` at `velocity` (cells, cells per tick) at the
  /// start of tick `tick`; a body followed already starts anew. With `thrown` false (a body an undo or
  /// a load brought back), a body that touches something in its first reading has landed already and
  /// gets no landing line.
  void follow(granular::BodyId id, std::uint64_t tick, granular::Vec3 position, granular::Vec3 velocity,
              bool thrown = true);
  /// Stops following every body not in `ids` (gone after an undo or a load).
  void keep_only(const std::vector<granular::BodyId>& ids);
  /// The bodies followed now.
  std::size_t size() const { return followed_.size(); }

  /// The bodies as the tick that started at `tick` wrote them: the lines for those that landed or
  /// came to rest in it ("body 3: landed in granular ...", "body 3: at rest ..."). A body not followed
  /// is ignored.
  std::vector<std::string> observe(std::uint64_t tick, const std::vector<BodyReading>& bodies);

  /// The ticks a free fall from height `z0` at vertical speed `vz` (cells, cells per tick, up
  /// positive) takes down to `z`, under g in cells per tick squared; 0 when z is above the path's top
  /// (it never gets there).
  static double fall_ticks(double z0, double vz, double z, double g_cells);

 private:
  struct Followed {
    std::uint64_t start_tick = 0;    // the tick it left its first position
    granular::Vec3 start, velocity;  // there, and how fast
    bool announce = true;            // false: brought back, its first reading may find it landed already
    bool landed = false;
    bool resting = false;
    granular::Vec3 rest_at;             // its centre when it came to rest
    std::deque<granular::Vec3> recent;  // its centre at the last kRestTicks ticks, oldest first
  };
  // The material it touches most (grains, liquids or static cells beside or under it), or -1.
  int touched(const granular::BodySand& sand) const;
  // The share of its cells below the surface of grains and liquids.
  static double submerged(const granular::BodySand& sand);

  granular::MaterialTable materials_;
  double g_cells_;  // gravity, cells per tick squared
  std::map<granular::BodyId, Followed> followed_;
};

}  // namespace viewer
