/// @file distributed_mpi.cpp
/// `granular run --distributed` (built only with MPI): the run split over the ranks of
/// MPI_COMM_WORLD. Each rank reads the scene and keeps its slab; rank 0 prints. A failure ends
/// every rank with exit status 1 and is printed once, by rank 0: the ranks catch what they fail
/// with, meet, and agree on it. A rank that fails alone while the others wait for it in an exchange
/// cannot meet them: after kPatienceSeconds it prints its error itself and ends every rank
/// (MPI_Abort), so no rank waits forever.

#include <cstdio>

#include "distributed_run.hpp"
#include "granular/mpi_communicator.hpp"
#include "granular/world_snapshot.hpp"

namespace granular::cli {

namespace {

/// How long a failed rank waits for the others to meet it before it ends them all.
constexpr double kPatienceSeconds = 20.0;

/// This rank's part of run_distributed: throws the failure every rank agreed on.
void run_distributed_rank(const RunOptions& o, MpiCommunicator& comm);

}  // namespace

void run_distributed(const RunOptions& o) {
  MpiSession session;
  MpiCommunicator comm;
  set_process_rank(comm.rank());
  try {
    run_distributed_rank(o, comm);
  } catch (...) {
    // Every rank holds the agreed failure. Rank 0 prints it while every rank is still in the job,
    // and the others wait for that: a rank that ended first with status 1 would make the launcher
    // stop the rest, rank 0's line unprinted.
    if (comm.rank() == 0) std::fprintf(stderr, "error: %s\n", error_text(std::current_exception()).c_str());
    std::fflush(nullptr);
    (void)comm.barrier_within(kPatienceSeconds);
    throw ErrorReported{1};
  }
}

namespace {

void run_distributed_rank(const RunOptions& o, MpiCommunicator& comm) {
  // Alone: the scene (every rank reads it) and the file to save to (rank 0 writes it), checked
  // before any tick runs. No rank waits for another here, so all of them meet below.
  WorldSource source;
  std::exception_ptr failure;
  try {
    if (comm.rank() == 0 && !o.save.empty()) check_snapshot_save_path(o.save);
    source = load_world_source(o.world, o.save.empty() ? kRunBytesPerCell : kSaveBytesPerCell);
  } catch (...) {
    failure = std::current_exception();
  }
  agree_on_failure(comm, failure);
  // Together.
  try {
    run_split_rank(o, source, comm);
  } catch (...) {
    failure = std::current_exception();
  }
  if (!comm.barrier_within(failure ? kPatienceSeconds : -1.0)) {
    // The others are waiting for this rank in an exchange: they cannot be told, only stopped.
    try {
      std::rethrow_exception(failure);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: rank %d: %s (ending every rank)\n", comm.rank(), e.what());
    } catch (...) {
      std::fprintf(stderr, "error: rank %d failed (ending every rank)\n", comm.rank());
    }
    std::fflush(nullptr);
    comm.abort(1);
  }
  agree_on_failure(comm, failure);
}

}  // namespace

}  // namespace granular::cli
