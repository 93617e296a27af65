/// @file test_mpi_communicator.cpp
/// MpiCommunicator under mpiexec (any number of ranks): send_receive around a ring and along a chain
/// (kNoRank at the ends), all_gather, both at lengths around the chunk size (a communicator with
/// 7-byte chunks runs the chunked paths that 1 GiB messages take), a message of the wrong length
/// and an all_gather of unequal lengths as CommunicatorErrors naming both counts (after which the
/// communicator still works), and the core's all_sum over it. Exit status 0 on every rank when all
/// checks hold; rank 0 prints the summary.

#include <cstdio>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "granular/mpi_communicator.hpp"

using granular::Communicator;
using granular::CommunicatorError;
using granular::MpiCommunicator;

namespace {

int failures = 0;

void expect(bool ok, const std::string& what, int rank) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "rank %d: FAILED: %s\n", rank, what.c_str());
}

/// The byte `i` of rank `r`'s message.
std::uint8_t pattern(int r, std::size_t i) { return std::uint8_t(r * 37 + i * 11 + 5); }

std::vector<std::uint8_t> message(int r, std::size_t length) {
  std::vector<std::uint8_t> m(length);
  for (std::size_t i = 0; i < length; ++i) m[i] = pattern(r, i);
  return m;
}

void exchanges(MpiCommunicator& comm, const std::string& name) {
  const int r = comm.rank(), n = comm.size();
  for (const std::size_t length : {0, 1, 6, 7, 8, 20, 1000}) {
    // A ring: to the next rank, from the previous one.
    std::vector<std::uint8_t> got(length, 0xEE);
    comm.send_receive((r + 1) % n, message(r, length), (r + n - 1) % n, got);
    expect(got == message((r + n - 1) % n, length), name + ": ring of " + std::to_string(length) + " bytes", r);
    // A chain, as the halo exchange: upwards, nobody below rank 0 and above the last.
    const int above = r + 1 < n ? r + 1 : Communicator::kNoRank;
    const int below = r > 0 ? r - 1 : Communicator::kNoRank;
    std::vector<std::uint8_t> from_below(below == Communicator::kNoRank ? 0 : length, 0xEE);
    comm.send_receive(above, message(r, length), below, from_below);
    expect(below == Communicator::kNoRank || from_below == message(below, length),
           name + ": chain of " + std::to_string(length) + " bytes", r);
    // all_gather
    std::vector<std::uint8_t> all(length * std::size_t(n), 0xEE);
    comm.all_gather(message(r, length), all);
    bool same = true;
    for (int k = 0; k < n; ++k)
      for (std::size_t i = 0; i < length; ++i) same = same && all[std::size_t(k) * length + i] == pattern(k, i);
    expect(same, name + ": all_gather of " + std::to_string(length) + " bytes per rank", r);
  }
  expect(granular::all_sum(comm, std::uint64_t(r + 1)) == std::uint64_t(n) * std::uint64_t(n + 1) / 2, name + ": all_sum", r);
}

void wrong_lengths(MpiCommunicator& comm, const std::string& name) {
  const int r = comm.rank(), n = comm.size();
  // Rank 0 sends 13 bytes around the ring where its neighbour expects 10; everyone else sends 10.
  const std::size_t length = r == 0 ? 13 : 10;
  std::vector<std::uint8_t> got(10);
  std::string error;
  try {
    comm.send_receive((r + 1) % n, message(r, length), (r + n - 1) % n, got);
  } catch (const CommunicatorError& e) {
    error = e.what();
  }
  if (r == 1 % n)
    expect(error.find("rank 0 sent 13 bytes") != std::string::npos && error.find("expected 10") != std::string::npos,
           name + ": the wrong length is named (got '" + error + "')", r);
  else
    expect(error.empty(), name + ": no error where the length was right (got '" + error + "')", r);
  // Unequal all_gather lengths: every rank throws.
  error.clear();
  try {
    std::vector<std::uint8_t> all(std::size_t(n) * (r == 0 ? 3 : 4));
    comm.all_gather(message(r, r == 0 ? 3 : 4), all);
  } catch (const CommunicatorError& e) {
    error = e.what();
  }
  expect(n == 1 || (error.find("passes") != std::string::npos && error.find("every rank must pass as many") != std::string::npos),
         name + ": unequal all_gather lengths are an error on every rank (got '" + error + "')", r);
  // Nothing is left over: the next exchange gets its own bytes.
  std::vector<std::uint8_t> next(5);
  comm.send_receive((r + 1) % n, message(r + 100, 5), (r + n - 1) % n, next);
  expect(next == message((r + n - 1) % n + 100, 5), name + ": the exchange after an error", r);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    granular::MpiSession session(&argc, &argv);
    {
      MpiCommunicator whole;  // 1 GiB chunks: every message here is one
      MpiCommunicator small(MPI_COMM_WORLD, 7);
      const int r = whole.rank();
      expect(whole.description() == "MPI, " + std::to_string(whole.size()) + (whole.size() == 1 ? " rank" : " ranks"),
             "description '" + whole.description() + "'", r);
      exchanges(whole, "1 GiB chunks");
      exchanges(small, "7-byte chunks");
      wrong_lengths(whole, "1 GiB chunks");
      wrong_lengths(small, "7-byte chunks");
      std::string bad_rank;
      try {
        std::vector<std::uint8_t> none;
        whole.send_receive(whole.size(), none, Communicator::kNoRank, none);
      } catch (const granular::InvalidArgument& e) {
        bad_rank = e.what();
      }
      expect(bad_rank.find("to = " + std::to_string(whole.size())) != std::string::npos, "a rank past the end is named", r);
      expect(whole.barrier_within(60), "barrier_within", r);
      const bool all_passed = granular::all_true(whole, failures == 0);
      if (r == 0)
        std::printf("mpi communicator: %s on %d ranks\n", all_passed ? "all checks passed" : "checks FAILED", whole.size());
      if (!all_passed) failures = failures ? failures : 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return failures == 0 ? 0 : 1;
}
