#pragma once
/// @file mpi_communicator.hpp
/// The MPI transport of a DistributedWorld (distributed_world.hpp): ranks that are MPI processes,
/// on one machine or a cluster. Part of granular_mpi (granular::mpi), which the build has when MPI
/// is found; the core never links MPI.
///
///     granular::MpiSession session(&argc, &argv);   // MPI_Init_thread, and MPI_Finalize at the end
///     granular::MpiCommunicator comm;                // MPI_COMM_WORLD
///     granular::DistributedWorld world(def, comm, grid);
///
/// Every MPI error is a CommunicatorError carrying MPI_Error_string's text.

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "granular/distributed/communicator.hpp"

namespace granular {

/// Starts MPI for the lifetime of this object: MPI_Init_thread, unless MPI is initialised already,
/// and MPI_Finalize on destruction when (and only when) this session initialised it. Make one
/// before any MpiCommunicator, and destroy the communicators first.
class MpiSession {
 public:
  /// Initialises MPI asking for thread support `required` (MPI_THREAD_FUNNELED: only the thread
  /// that made the session calls MPI), passing `argc`/`argv` on to MPI_Init_thread (either may be
  /// null). Throws CommunicatorError when initialisation fails or MPI provides less than
  /// `required` (then it finalises again).
  explicit MpiSession(int* argc = nullptr, char*** argv = nullptr, int required = MPI_THREAD_FUNNELED);
  /// Finalises MPI when this session initialised it and it was not finalised since.
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  /// True when this session called MPI_Init_thread (false: MPI was running already).
  bool initialised_here() const { return initialised_here_; }
  /// The thread support MPI provides (MPI_THREAD_SINGLE .. MPI_THREAD_MULTIPLE).
  int thread_level() const { return thread_level_; }

 private:
  bool initialised_here_ = false;
  int thread_level_ = MPI_THREAD_SINGLE;
};

/// One rank of an MPI communicator as a granular Communicator. It exchanges its messages on a
/// duplicate of the communicator it is given (which it does not own, and which must stay valid
/// while this object lives), so they never match the program's own messages, and that duplicate
/// returns error codes instead of aborting: every failure is a CommunicatorError.
class MpiCommunicator final : public Communicator {
 public:
  /// Largest number of bytes one MPI call carries (1 GiB; MPI counts are ints): longer messages go
  /// in chunks of this size.
  static constexpr std::size_t kMaxChunkBytes = std::size_t(1) << 30;

  /// Wraps `comm` (MPI_COMM_WORLD by default). `chunk_bytes` (1 .. kMaxChunkBytes) is the longest
  /// piece one MPI call carries, smaller only to test the chunking. MPI must be initialised (an
  /// MpiSession); CommunicatorError otherwise, InvalidArgument for a bad `chunk_bytes`. Collective
  /// over `comm` (it duplicates it).
  explicit MpiCommunicator(MPI_Comm comm = MPI_COMM_WORLD, std::size_t chunk_bytes = kMaxChunkBytes);
  /// Frees the duplicate (unless MPI was finalised already).
  ~MpiCommunicator() override;
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;

  /// This process's rank in the communicator.
  int rank() const override { return rank_; }
  /// Processes in the communicator.
  int size() const override { return size_; }
  /// "MPI, N ranks".
  std::string description() const override;
  /// MPI_Sendrecv of `send` to rank `to` and `receive` from rank `from` (kNoRank: MPI_PROC_NULL),
  /// in chunks of at most chunk_bytes. Throws CommunicatorError naming both counts when `from` sends
  /// another number of bytes than `receive` holds, and for every MPI error.
  void send_receive(int to, std::span<const std::uint8_t> send, int from, std::span<std::uint8_t> receive) override;
  /// MPI_Allgather of `mine` into `all`, in chunks of at most chunk_bytes per rank. Throws
  /// CommunicatorError when the ranks pass different numbers of bytes (naming both counts), when
  /// `all` is not size() times `mine`, and for every MPI error.
  void all_gather(std::span<const std::uint8_t> mine, std::span<std::uint8_t> all) override;

  /// Waits until every rank has called this (MPI_Ibarrier), for at most `seconds` (a negative value:
  /// no limit). Returns false when the time ran out: some rank is elsewhere (waiting for this one in
  /// another exchange, or gone), and the only call left to make on this communicator is abort().
  bool barrier_within(double seconds);
  /// Ends every process of the communicator with exit status `status` (MPI_Abort): what a rank that
  /// failed alone does when the others cannot learn of it.
  [[noreturn]] void abort(int status);
  /// The duplicate this communicator exchanges on.
  MPI_Comm comm() const { return comm_; }

 private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0;
  int size_ = 1;
  std::size_t chunk_bytes_ = kMaxChunkBytes;
};

}  // namespace granular
