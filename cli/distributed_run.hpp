#pragma once
/// @file distributed_run.hpp
/// `granular run --domains N` and, in a build with MPI, `granular run --distributed`: the same run
/// as a plain `granular run` (scene, size, rules, ticks, seed, backend), but as a DistributedWorld
/// split into z-slabs, over N in-process ranks (threads of this process: several slabs on one GPU
/// or CPU) or over the MPI ranks the program was started on (`mpirun -n R granular run
/// --distributed ...`). Rank 0 alone prints progress, the summary (with the split) and errors;
/// the hash is the one a plain run prints.

#include <CLI/CLI.hpp>
#include <exception>
#include <string>

#include "granular/distributed/communicator.hpp"
#include "run_command.hpp"
#include "scene_runner.hpp"

namespace granular::cli {

/// Adds --domains (always) and --distributed (only in a build with MPI) to the run subcommand.
void add_split_options(CLI::App& run_command, RunOptions& options);

/// Runs `options` split when it asks for --domains or --distributed and returns true; false for a
/// plain run. Throws InvalidArgument for both options together.
bool run_split_if_asked(const RunOptions& options);

/// One rank's part of a split run of `source`: builds its slab, runs the ticks with the scene's
/// emitters, counts, hashes, saves (--save: rank 0 writes the whole world's snapshot) and, on
/// rank 0, prints the notices, progress and summary. Collective over `comm`.
void run_split_rank(const RunOptions& options, const WorldSource& source, Communicator& comm);

/// Collective: every rank passes what it failed with (null when it did not). Returns when no rank
/// failed; otherwise every rank throws the same failure: the lowest rank's that is not a
/// CommunicatorError (a rank that stopped because another failed), else the lowest rank's; the
/// rank that failed so rethrows its own exception, the others an Error "rank R: what".
void agree_on_failure(Communicator& comm, std::exception_ptr failure);

/// The `error:` line's text for a failure (granular::Error and other exceptions: their message; a
/// failed allocation: that it was one).
std::string error_text(std::exception_ptr failure);

/// Thrown once a failure is printed (or left to rank 0 to print): main exits with `status` and
/// prints nothing more.
struct ErrorReported {
  int status = 1;  ///< the exit status
};

/// Records this process's MPI rank once MPI runs: only rank 0 prints errors (prints_errors).
void set_process_rank(int rank);

/// Whether this process prints its errors: not an MPI rank, or rank 0. Before MPI is started
/// (command-line errors under mpirun) the launcher's environment says (OMPI_COMM_WORLD_RANK,
/// PMIX_RANK, PMI_RANK).
bool prints_errors();

#ifdef GRANULAR_CLI_HAS_MPI
/// `--distributed`: `options` split over the ranks of MPI_COMM_WORLD (distributed_mpi.cpp).
void run_distributed(const RunOptions& options);
#endif

}  // namespace granular::cli
