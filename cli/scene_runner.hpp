#pragma once
/// @file scene_runner.hpp
/// What `run` and `export` share: the world options, reading a scene, grid file or snapshot and
/// building the world from it, and running ticks with the scene's emitters and a progress bar.

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "progress_bar.hpp"

namespace granular::cli {

/// Largest --ticks: a million million ticks (far beyond any run that ends; a cap keeps the tick
/// arithmetic and progress figures exact).
inline constexpr std::uint64_t kMaxTicks = 1'000'000'000'000ull;

/// Bytes per cell a `run` holds at its peak: the scene's grid and the world's copy.
inline constexpr double kRunBytesPerCell = 2.0;

/// Bytes per cell an `export` holds: a run's, plus the snapshot it writes.
inline constexpr double kExportBytesPerCell = 3.0;

/// Bytes per cell a `run --save` holds at its peak: the world's cells, their copy for the snapshot
/// and the compressed snapshot (at most about one byte per cell).
inline constexpr double kSaveBytesPerCell = 3.0;

/// Memory a world needs besides its cells: the transition tables (about 130 MiB) and the worker
/// threads' stacks and allocation arenas.
inline constexpr double kWorldOverheadBytes = 256.0 * 1024 * 1024;

/// Options that define the world.
struct WorldOptions {
  std::string scene = "bowl";  ///< scene name, scene .json path, a .raw/.vox grid file or a .gsnap snapshot
  int size = 0;                ///< scene size parameter N (0: not given, the scene's default_n)
  std::string rules = WorldDef{}.rules; ///< rule-set preset
  std::string backend = "auto";///< auto, cpu or cuda
  int threads = 0;             ///< CPU threads (0 = all)
  std::uint64_t seed = 0;      ///< seed of random choices
  bool no_lut_cache = false;   ///< build the transition table even when cached
  bool dense = false;          ///< step every block every tick (no activity tracking)
  std::optional<double> dense_fraction;  ///< both WorldDef::cuda fractions when given
  bool rules_given = false;    ///< --rules was on the command line (a snapshot has rules of its own)
  bool seed_given = false;     ///< --seed was on the command line (a snapshot has a seed of its own)
};

/// Registers the world options on a subcommand.
void add_world_options(CLI::App& command, WorldOptions& options);

/// Registers `-t,--ticks` (0..kMaxTicks) on a subcommand.
void add_ticks_option(CLI::App& command, std::uint64_t& ticks, const std::string& description);

/// What a world is made from: a scene's grid and emitters, a grid file's cells, or a snapshot to
/// continue, with the definition the options give.
struct WorldSource {
  std::string scene_name;                      ///< scene name, grid file or snapshot
  std::optional<int> n;                        ///< the size parameter used; none for a grid file or snapshot
  std::optional<std::uint64_t> snapshot_tick;  ///< the tick a snapshot continues from; none for the rest
  std::vector<Emitter> emitters;               ///< the scene's emitters, in cells
  WorldDef def;                                ///< rules, seed, backend, threads... (a snapshot's own rules)
  Grid grid;                                   ///< the starting cells of a scene or grid file
  std::optional<WorldSnapshot> snapshot;       ///< or the snapshot to continue
  std::vector<std::string> notices;            ///< what reading the file noticed (a lossy .vox), to print
};

/// Reads what the options name (throws granular::Error on bad input). Before any grid is allocated,
/// the grid's size is checked against the memory this process may allocate at `bytes_per_cell`
/// (kRunBytesPerCell, kExportBytesPerCell) plus kWorldOverheadBytes, and a failed allocation is an
/// OutOfMemory naming the size. A snapshot continues under its own rules and seed: --rules or
/// --seed naming others is an InvalidArgument, as is --size.
WorldSource load_world_source(const WorldOptions& options, double bytes_per_cell);

/// A world made from the options, with the scene's emitters.
struct PreparedWorld {
  std::string scene_name;                ///< scene name, grid file or snapshot
  std::optional<int> n;                  ///< the size parameter used; none for a grid file or snapshot
  std::optional<std::uint64_t> snapshot_tick;  ///< the tick a snapshot continues from; none for the rest
  std::vector<Emitter> emitters;         ///< the scene's emitters, in cells
  std::unique_ptr<World> world;          ///< the world
  std::uint64_t brick_ticks = 0;         ///< bricks stepped, summed over every tick run_ticks ran
  MaterialCounts poured{};               ///< cells the scene's emitters poured, per material, over run_ticks
  std::uint64_t cell_ticks = 0;          ///< cells in stepped bricks, summed likewise
};

/// Builds the world from load_world_source(options, bytes_per_cell) and prints the file's and the
/// world's notices to stderr.
PreparedWorld prepare_world(const WorldOptions& options, double bytes_per_cell);

/// The ticks of the next World::step call when `done` of `total` ticks are done: 1 when
/// `per_tick` (emitters pour before every tick), else about total / 200 (so the per-call overhead
/// vanishes), never more than what is left nor more than an int holds; 0 when done == total.
int tick_chunk(std::uint64_t total, std::uint64_t done, bool per_tick);

/// Runs `ticks` ticks of `world` (a World, or one rank's DistributedWorld: then every rank calls it
/// alike) in steps of tick_chunk ticks, the scene's `emitters` pouring before each tick (what they
/// pour is added to `poured`), calling `after_step()` after each step, and drawing a progress bar
/// when `progress`; returns the wall seconds spent stepping.
template <class W, class AfterStep>
double step_world(W& world, const std::vector<Emitter>& emitters, std::uint64_t ticks, bool progress,
                  MaterialCounts& poured, AfterStep&& after_step) {
  ProgressBar bar("ticks", ticks, progress);
  double seconds = 0;
  for (std::uint64_t done = 0; done < ticks;) {
    const int n = tick_chunk(ticks, done, !emitters.empty());
    if (!emitters.empty()) {
      const MaterialCounts p = run_emitters(world, emitters);
      for (int m = 0; m < kMaterialCount; ++m) poured[m] += p[m];
    }
    const auto start = std::chrono::steady_clock::now();
    world.step(n);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    after_step();
    done += std::uint64_t(n);
    bar.update(done);
  }
  bar.finish();
  return seconds;
}

/// Runs `ticks` ticks of a prepared world (step_world), counting its stepped bricks and cells;
/// returns the wall seconds spent stepping.
double run_ticks(PreparedWorld& prepared, std::uint64_t ticks, bool progress);

}  // namespace granular::cli
