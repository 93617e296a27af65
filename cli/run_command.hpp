#pragma once
/// @file run_command.hpp
/// `granular run`: run a scene headless and print a summary; with --domains or --distributed, the
/// same run split into z-slabs (distributed_run.hpp).

#include <CLI/CLI.hpp>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "granular/material.hpp"
#include "granular/world.hpp"
#include "scene_runner.hpp"

namespace granular::cli {

/// The options of `granular run`.
struct RunOptions {
  WorldOptions world;
  std::uint64_t ticks = 1000;
  std::string save;  ///< snapshot written after the last tick ("" for none)
  bool json = false;
  bool no_progress = false;
  int domains = 0;           ///< --domains N: N in-process sub-domains (0: not given)
  bool distributed = false;  ///< --distributed: one sub-domain per MPI rank (builds with MPI)
};

/// The active bricks of a run on one World (none for a split run).
struct ActivitySummary {
  ActivityStats last;             ///< the last tick's
  std::uint64_t brick_ticks = 0;  ///< bricks stepped, summed over the ticks
  std::uint64_t cell_ticks = 0;   ///< cells in stepped bricks, summed likewise
};

/// How a split run divided the world (--domains, --distributed).
struct SplitSummary {
  std::string transport;                  ///< Communicator::description ("MPI, 3 ranks")
  int halo = 0;                           ///< layers kept beyond each inner boundary
  std::vector<std::array<int, 2>> slabs;  ///< each rank's owned layers [z0, z1)
  std::vector<double> exchange_seconds;   ///< each rank's seconds bringing halos up to date
  std::uint64_t exchange_bytes = 0;       ///< bytes all ranks sent to their neighbours
};

/// Everything a run's summary prints.
struct RunSummary {
  std::string scene_name;
  std::optional<int> n;                        ///< none for a grid file or a snapshot
  std::optional<std::uint64_t> snapshot_tick;  ///< the tick a snapshot continued from
  Int3 size{};
  std::string rules;
  std::uint64_t seed = 0;
  std::string backend;  ///< World::backend_description (of each rank's World for a split run)
  bool sparse = true;
  double lut_seconds = 0;
  bool lut_from_cache = false;
  std::uint64_t lut_hash = 0;
  double tick_seconds = 0;  ///< simulated seconds per tick (time_scale.hpp)
  std::uint64_t ticks = 0;
  double seconds = 0;
  MaterialCounts before{}, after{}, poured{};
  std::uint64_t hash = 0;
  std::uint64_t tick = 0;  ///< the world's tick at the end
  std::string saved;       ///< the snapshot written ("" for none)
  std::optional<ActivitySummary> activity;
  std::optional<SplitSummary> split;
};

/// The summary's fields that `world` (a World, or a split run's rank-0 slab) gives: rules, seed,
/// backend, stepping, table.
void describe_world(RunSummary& summary, const World& world);

/// Prints the summary on stdout, as text or as JSON.
void print_run_summary(const RunSummary& summary, bool json);

/// Adds the `run` subcommand to `app`.
void add_run_command(CLI::App& app);

}  // namespace granular::cli
