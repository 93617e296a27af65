#pragma once
/// @file pour_cone.hpp
/// The poured-cone experiment: grains (sand, or any granular material of the table) poured from a
/// small spout onto a flat floor, left to settle, then measured with measure_cone.

#include <cstdint>
#include <limits>

#include "granular/accuracy/cone_metrics.hpp"
#include "granular/grid.hpp"
#include "granular/material.hpp"
#include "granular/world_def.hpp"

namespace granular::accuracy {

/// What pour_cone produced.
struct PourResult {
  Grid grid;                  ///< the settled grid
  ConeMetrics metrics;        ///< measure_cone of `grid` (the poured material) around the spout's axis, floor_z = 1
  double seconds = 0;         ///< wall-clock time of pouring and settling (world creation excluded)
  std::uint64_t ticks = 0;    ///< ticks stepped in all (pouring + settling)
  MaterialCounts before{};    ///< cell counts after the floor was laid, before any pour
  MaterialCounts after{};     ///< cell counts of `grid`
  std::uint64_t poured = 0;   ///< grains the pour calls added
  std::uint64_t pour_ticks = 0;  ///< ticks stepped while pouring (the first `ticks`, or until `max_grains` were poured)
  bool settled = false;       ///< true when the grid came to rest within settle_ticks
  bool conserved = false;     ///< every material's count changed by the grains poured alone (void lost them)
};

/// Pours a cone: a world of floor_size x floor_size x height cells (`base` gives rules, seed,
/// backend, threads, cache; its size is replaced), a Solid floor layer at z = 0, then for `ticks`
/// ticks, or until `max_grains` grains have been poured: World::pour(`grains_per_tick` cells of
/// `material`, no more than `max_grains` in all, sphere of radius `spout_radius` centred at
/// (floor_size / 2, floor_size / 2, height - 2 - spout_radius)) followed by one step; then up to
/// `settle_ticks` more ticks in 8-tick cycles, stopping after the first cycle whose end hash equals
/// its start hash. The pile is measured with measure_cone(grid, spout centre, 1, material).
/// `spout_radius` (default 2) sets the sphere's radius: a wider spout pours more grains per tick.
/// Throws InvalidArgument for floor_size < 8, height < 8, grains_per_tick < 0, spout_radius outside
/// [1, height / 4], a material that is not granular in the rule set's table (and whatever World throws).
PourResult pour_cone(const WorldDef& base, int floor_size, int height, std::int64_t grains_per_tick,
                     std::uint64_t ticks, std::uint64_t settle_ticks, double spout_radius = 2.0,
                     Material material = Material::Granular,
                     std::uint64_t max_grains = std::numeric_limits<std::uint64_t>::max());

}  // namespace granular::accuracy
