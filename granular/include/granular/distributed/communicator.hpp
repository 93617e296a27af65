#pragma once
/// @file distributed/communicator.hpp
/// How the ranks of a DistributedWorld (distributed_world.hpp) exchange bytes: the point-to-point
/// and all-gather operations the slab decomposition needs, behind an interface a transport
/// implements. The core has one for ranks that are threads of one process (LocalGroup,
/// local_group.hpp); granular_mpi has one for MPI ranks (mpi_communicator.hpp).
///
/// Every rank calls the same operations in the same order (collectively, as in MPI). Messages from
/// one rank to another arrive in the order they were sent.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace granular {

/// One rank's view of a group of ranks.
class Communicator {
 public:
  /// The rank argument meaning "nobody": nothing is sent, or nothing received.
  static constexpr int kNoRank = -1;

  virtual ~Communicator() = default;
  /// This rank, 0 .. size() - 1.
  virtual int rank() const = 0;
  /// Ranks in the group.
  virtual int size() const = 0;
  /// The transport, for messages ("in-process, 4 ranks", "MPI, 4 ranks").
  virtual std::string description() const = 0;
  /// Sends `send` to rank `to` and receives exactly `receive.size()` bytes from rank `from` (who
  /// sends as many); either rank may be kNoRank. Returns when `receive` is filled and `send` may be
  /// reused. Throws CommunicatorError on a transport failure or a message of another size.
  virtual void send_receive(int to, std::span<const std::uint8_t> send, int from, std::span<std::uint8_t> receive) = 0;
  /// Fills `all` (size() times as many bytes as `mine`) with every rank's `mine` in rank order;
  /// every rank passes as many bytes. Throws CommunicatorError as send_receive.
  virtual void all_gather(std::span<const std::uint8_t> mine, std::span<std::uint8_t> all) = 0;
};

/// The sum over the ranks of `value` (modulo 2^64), on every rank.
std::uint64_t all_sum(Communicator& comm, std::uint64_t value);

/// The element-wise sum over the ranks of `values`, on every rank.
std::vector<std::uint64_t> all_sum(Communicator& comm, std::span<const std::uint64_t> values);

/// True on every rank when `ok` is true on every rank: how the ranks agree that a step each took
/// alone (an allocation, a file write) worked before any of them goes on.
bool all_true(Communicator& comm, bool ok);

/// Every rank's `mine` (any number of bytes, which may differ from rank to rank), in rank order.
std::vector<std::vector<std::uint8_t>> all_gather_bytes(Communicator& comm, std::span<const std::uint8_t> mine);

}  // namespace granular
