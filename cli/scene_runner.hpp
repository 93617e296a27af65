#pragma once
/// @file scene_runner.hpp
/// What `run` and `export` share: the world options, building the world from a scene or grid file,
/// and running ticks with the scene's emitters and a progress bar.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "granular/world.hpp"

namespace granular::cli {

/// Options that define the world.
struct WorldOptions {
  std::string scene = "bowl";  ///< scene name, scene .json path, or a .raw/.vox grid file
  int size = 0;                ///< scene size parameter N (0 = the scene's default)
  std::string rules = WorldDef{}.rules; ///< rule-set preset
  std::string backend = "auto";///< auto, cpu or cuda
  int threads = 0;             ///< CPU threads (0 = all)
  std::uint64_t seed = 0;      ///< seed of random choices
  bool no_lut_cache = false;   ///< build the transition table even when cached
  bool dense = false;          ///< step every block every tick (no activity tracking)
};

/// Registers the world options on a subcommand.
void add_world_options(CLI::App& command, WorldOptions& options);

/// A world made from the options, with the scene's emitters.
struct PreparedWorld {
  std::string scene_name;                ///< scene name or grid file
  int n = 0;                             ///< the size parameter used (0 for grid files)
  std::vector<Emitter> emitters;         ///< the scene's emitters, in cells
  std::unique_ptr<World> world;          ///< the world
  std::uint64_t brick_ticks = 0;         ///< bricks stepped, summed over every tick run_ticks ran
  std::uint64_t cell_ticks = 0;          ///< cells in stepped bricks, summed likewise
};

/// Builds the world (throws granular::Error on bad input) and prints its notices to stderr.
PreparedWorld prepare_world(const WorldOptions& options);

/// Runs `ticks` ticks (feeding emitters before each tick when the scene has any), drawing a
/// progress bar when `progress`; returns the wall seconds spent stepping.
double run_ticks(PreparedWorld& prepared, std::uint64_t ticks, bool progress);

}  // namespace granular::cli
