#pragma once
/// @file distributed/local_group.hpp
/// Ranks that are threads of one process: the Communicator of a DistributedWorld split into
/// sub-domains in one program (several slabs on one GPU or CPU, the tests), with no MPI.

#include <functional>
#include <memory>

#include "granular/distributed/communicator.hpp"

namespace granular {

/// A group of `size` ranks exchanging bytes through this process's memory. Each rank's
/// communicator (rank(r)) is used by one thread. When a rank fails (fail()), every rank waiting
/// for it, or later asking for it, gets a CommunicatorError instead of waiting forever.
class LocalGroup {
 public:
  /// A group of `size` ranks, 1..4096; InvalidArgument naming the value otherwise.
  explicit LocalGroup(int size);
  ~LocalGroup();
  LocalGroup(const LocalGroup&) = delete;
  LocalGroup& operator=(const LocalGroup&) = delete;
  /// Ranks in the group.
  int size() const;
  /// The communicator of rank `r` (0 .. size() - 1).
  Communicator& rank(int r);
  /// Marks rank `r` failed with `why`: every rank's pending and later exchanges throw.
  void fail(int r, const std::string& why);

 private:
  struct Shared;
  class RankCommunicator;
  std::unique_ptr<Shared> shared_;
};

/// Runs fn(communicator) on `ranks` threads, one per rank of a LocalGroup, and returns when all
/// are done; rethrows the exception of the lowest failing rank (a failing rank fails the group, so
/// the others stop too).
void run_local_ranks(int ranks, const std::function<void(Communicator&)>& fn);

}  // namespace granular
