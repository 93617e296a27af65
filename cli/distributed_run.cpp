#include "distributed_run.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "granular/distributed/distributed_world.hpp"
#include "granular/errors.hpp"
#include "granular/distributed/local_group.hpp"
#include "granular/world_snapshot.hpp"
#include "number_option.hpp"

namespace granular::cli {

namespace {

/// Most in-process sub-domains --domains takes.
constexpr int kMaxDomains = 64;

/// This process's MPI rank once MPI runs; -1 before (or without) MPI.
std::atomic<int> process_rank{-1};

/// Every rank's exchange seconds, in rank order, on every rank.
std::vector<double> gather_seconds(Communicator& comm, double mine) {
  std::vector<double> all(std::size_t(comm.size()));
  comm.all_gather({reinterpret_cast<const std::uint8_t*>(&mine), sizeof mine},
                  {reinterpret_cast<std::uint8_t*>(all.data()), all.size() * sizeof(double)});
  return all;
}

/// --domains N: the world split over N ranks that are threads of this process.
void run_domains(const RunOptions& o) {
  // Everything about the snapshot to write that can be wrong is found before any tick is run.
  if (!o.save.empty()) check_snapshot_save_path(o.save);
  const WorldSource source = load_world_source(o.world, o.save.empty() ? kRunBytesPerCell : kSaveBytesPerCell);
  run_local_ranks(o.domains, [&](Communicator& comm) { run_split_rank(o, source, comm); });
}

}  // namespace

void add_split_options(CLI::App& cmd, RunOptions& o) {
  add_number_option(cmd, "--domains", o.domains, {1, std::uint64_t(kMaxDomains), ""},
                    "run the world as N z-slab sub-domains in this process (threads exchanging halos; each slab's "
                    "World runs --threads threads), e.g. several slabs on one GPU; the same hash as one domain")
      ->default_str("");
#ifdef GRANULAR_CLI_HAS_MPI
  cmd.add_flag("--distributed", o.distributed,
               "run the world as one z-slab per MPI rank (start with `mpirun -n R granular run --distributed ...`); "
               "rank 0 prints the progress and the summary; the same hash as one domain");
#endif
}

bool run_split_if_asked(const RunOptions& o) {
  if (o.distributed && o.domains != 0)
    throw InvalidArgument("--domains " + std::to_string(o.domains) +
                          ": cannot be combined with --distributed, which splits the world over the MPI ranks "
                          "(use one or the other)");
#ifdef GRANULAR_CLI_HAS_MPI
  if (o.distributed) {
    run_distributed(o);
    return true;
  }
#endif
  if (o.domains == 0) return false;
  run_domains(o);
  return true;
}

void run_split_rank(const RunOptions& o, const WorldSource& source, Communicator& comm) {
  const bool root = comm.rank() == 0;
  if (root)
    for (const auto& notice : source.notices) std::fprintf(stderr, "notice: %s\n", notice.c_str());
  std::unique_ptr<DistributedWorld> made = source.snapshot
                                               ? std::make_unique<DistributedWorld>(source.def, comm, *source.snapshot)
                                               : std::make_unique<DistributedWorld>(source.def, comm, source.grid);
  DistributedWorld& w = *made;
  if (root)
    for (const auto& notice : w.slab().notices()) std::fprintf(stderr, "notice: %s\n", notice.c_str());
  RunSummary r;
  r.before = w.count();
  double exchange_seconds = 0;
  std::uint64_t exchange_bytes = 0;
  r.seconds = step_world(w, source.emitters, o.ticks, root && !o.no_progress, r.poured, [&] {
    exchange_seconds += w.last_exchange().seconds;
    exchange_bytes += w.last_exchange().bytes_sent;
  });
  r.after = w.count();
  r.hash = w.hash();
  SplitSummary split;
  split.transport = comm.description();
  split.halo = w.layout().halo();
  for (int k = 0; k < comm.size(); ++k) split.slabs.push_back({w.layout().slab(k).z0, w.layout().slab(k).z1});
  split.exchange_seconds = gather_seconds(comm, exchange_seconds);
  split.exchange_bytes = all_sum(comm, exchange_bytes);
  if (!o.save.empty()) {
    w.save(o.save);  // each rank compresses its slab; rank 0 writes the file
    r.saved = o.save;
  }
  if (!root) return;
  r.scene_name = source.scene_name;
  r.n = source.n;
  r.snapshot_tick = source.snapshot_tick;
  r.size = w.size();
  describe_world(r, w.slab());
  r.ticks = o.ticks;
  r.tick = w.tick();
  r.split = std::move(split);
  print_run_summary(r, o.json);
}

void agree_on_failure(Communicator& comm, std::exception_ptr failure) {
  // Each rank's failure as bytes: a kind (0 none, 1 a CommunicatorError, 2 another) and the message.
  std::string mine(1, '\0');
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const CommunicatorError& e) {
      mine = std::string(1, '\1') + e.what();
    } catch (const std::exception& e) {
      mine = std::string(1, '\2') + e.what();
    } catch (...) {
      mine = std::string(1, '\2') + "an exception that is not a std::exception";
    }
  }
  const std::vector<std::vector<std::uint8_t>> all =
      all_gather_bytes(comm, {reinterpret_cast<const std::uint8_t*>(mine.data()), mine.size()});
  int chosen = -1;
  for (const int kind : {2, 1}) {
    for (int r = 0; r < comm.size() && chosen < 0; ++r)
      if (!all[std::size_t(r)].empty() && all[std::size_t(r)][0] == kind) chosen = r;
    if (chosen >= 0) break;
  }
  if (chosen < 0) return;
  if (chosen == comm.rank()) std::rethrow_exception(failure);
  const auto& bytes = all[std::size_t(chosen)];
  const std::string what(bytes.begin() + 1, bytes.end());
  if (bytes[0] == 1) throw CommunicatorError("rank " + std::to_string(chosen) + ": " + what);
  throw Error("rank " + std::to_string(chosen) + ": " + what);
}

std::string error_text(std::exception_ptr failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const std::bad_alloc&) {
    return "out of memory (an allocation failed outside the checked grid allocations)";
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

void set_process_rank(int rank) { process_rank = rank; }

bool prints_errors() {
  if (process_rank >= 0) return process_rank == 0;
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* value = std::getenv(name); value && *value) return std::strcmp(value, "0") == 0;
  return true;
}

}  // namespace granular::cli
