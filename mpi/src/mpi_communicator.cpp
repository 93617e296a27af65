#include "granular/mpi_communicator.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>
#include <vector>

#include "granular/errors.hpp"

namespace granular {

namespace {

/// Tags of the two messages of a send_receive: the length, then the bytes.
constexpr int kLengthTag = 0x6772;
constexpr int kBytesTag = 0x6773;

/// Throws CommunicatorError "<what>: <MPI's text for code>" unless code is MPI_SUCCESS.
void check(int code, const std::string& what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING] = {};
  int length = 0;
  if (MPI_Error_string(code, text, &length) != MPI_SUCCESS) length = 0;
  throw CommunicatorError(what + ": " + (length > 0 ? std::string(text, std::size_t(length)) : "MPI error code " + std::to_string(code)));
}

/// MPI's rank for a Communicator rank (kNoRank: MPI_PROC_NULL), checked against `size`.
int mpi_rank(int rank, int size, const char* what) {
  if (rank == Communicator::kNoRank) return MPI_PROC_NULL;
  if (rank < 0 || rank >= size)
    throw InvalidArgument(std::string("MpiCommunicator::send_receive: ") + what + " = " + std::to_string(rank) +
                          " is neither a rank 0.." + std::to_string(size - 1) + " nor kNoRank");
  return rank;
}

/// The chunks a message of `bytes` goes in (a message of no bytes is still one, empty).
std::size_t chunk_count(std::size_t bytes, std::size_t chunk) { return std::max<std::size_t>(1, (bytes + chunk - 1) / chunk); }

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv, int required) {
  int initialised = 0, finalised = 0;
  check(MPI_Initialized(&initialised), "MPI_Initialized");
  check(MPI_Finalized(&finalised), "MPI_Finalized");
  if (finalised) throw CommunicatorError("MpiSession: MPI was finalised already in this process and cannot start again");
  if (initialised) {
    check(MPI_Query_thread(&thread_level_), "MPI_Query_thread");
    return;
  }
  check(MPI_Init_thread(argc, argv, required, &thread_level_), "MPI_Init_thread");
  initialised_here_ = true;
  if (thread_level_ < required) {
    MPI_Finalize();
    initialised_here_ = false;
    throw CommunicatorError("MpiSession: MPI provides thread support level " + std::to_string(thread_level_) +
                            ", below the level " + std::to_string(required) + " asked for");
  }
}

MpiSession::~MpiSession() {
  if (!initialised_here_) return;
  int finalised = 1;
  if (MPI_Finalized(&finalised) == MPI_SUCCESS && !finalised) MPI_Finalize();
}

MpiCommunicator::MpiCommunicator(MPI_Comm comm, std::size_t chunk_bytes) : chunk_bytes_(chunk_bytes) {
  if (chunk_bytes < 1 || chunk_bytes > kMaxChunkBytes)
    throw InvalidArgument("MpiCommunicator: chunk_bytes = " + std::to_string(chunk_bytes) + " is outside 1.." +
                          std::to_string(kMaxChunkBytes));
  int initialised = 0, finalised = 0;
  check(MPI_Initialized(&initialised), "MPI_Initialized");
  check(MPI_Finalized(&finalised), "MPI_Finalized");
  if (!initialised || finalised)
    throw CommunicatorError(std::string("MpiCommunicator: MPI is ") + (finalised ? "finalised" : "not initialised") +
                            " (make a granular::MpiSession first, and keep it while communicators live)");
  check(MPI_Comm_dup(comm, &comm_), "MPI_Comm_dup");
  try {
    check(MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
    check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
  } catch (...) {
    MPI_Comm_free(&comm_);
    throw;
  }
}

MpiCommunicator::~MpiCommunicator() {
  int finalised = 1;
  if (comm_ != MPI_COMM_NULL && MPI_Finalized(&finalised) == MPI_SUCCESS && !finalised) MPI_Comm_free(&comm_);
}

std::string MpiCommunicator::description() const {
  return "MPI, " + std::to_string(size_) + (size_ == 1 ? " rank" : " ranks");
}

void MpiCommunicator::send_receive(int to, std::span<const std::uint8_t> send, int from, std::span<std::uint8_t> receive) {
  const int dest = mpi_rank(to, size_, "to");
  const int source = mpi_rank(from, size_, "from");
  // The length goes first, so a receiver expecting another length still takes every chunk the
  // sender sends (no sender is left waiting) and can name both counts.
  std::uint64_t length = send.size(), theirs = 0;
  check(MPI_Sendrecv(&length, 1, MPI_UINT64_T, dest, kLengthTag, &theirs, 1, MPI_UINT64_T, source, kLengthTag, comm_,
                     MPI_STATUS_IGNORE),
        "MpiCommunicator::send_receive: MPI_Sendrecv of the length to rank " + std::to_string(to) + " and from rank " +
            std::to_string(from));
  if (source == MPI_PROC_NULL) theirs = 0;
  const bool fits = theirs == receive.size();
  std::vector<std::uint8_t> scratch;  // where a message of the wrong length goes
  if (!fits && theirs > receive.size()) scratch.resize(std::size_t(std::min<std::uint64_t>(theirs, chunk_bytes_)));
  const std::size_t sends = dest == MPI_PROC_NULL ? 0 : chunk_count(send.size(), chunk_bytes_);
  const std::size_t receives = source == MPI_PROC_NULL ? 0 : chunk_count(std::size_t(theirs), chunk_bytes_);
  for (std::size_t i = 0; i < std::max(sends, receives); ++i) {
    const std::size_t at = i * chunk_bytes_;
    const int send_count = i < sends ? int(std::min(chunk_bytes_, send.size() - std::min(at, send.size()))) : 0;
    const int receive_count = i < receives ? int(std::min<std::uint64_t>(chunk_bytes_, theirs - std::min<std::uint64_t>(at, theirs))) : 0;
    std::uint8_t* into = !scratch.empty() ? scratch.data() : receive_count > 0 ? receive.data() + at : receive.data();
    MPI_Status status;
    check(MPI_Sendrecv(send_count > 0 ? send.data() + at : send.data(), send_count, MPI_BYTE,
                       i < sends ? dest : MPI_PROC_NULL, kBytesTag, into, receive_count, MPI_BYTE,
                       i < receives ? source : MPI_PROC_NULL, kBytesTag, comm_, &status),
          "MpiCommunicator::send_receive: MPI_Sendrecv of " + std::to_string(send.size()) + " bytes to rank " +
              std::to_string(to) + " and " + std::to_string(receive.size()) + " bytes from rank " + std::to_string(from));
    if (i < receives) {
      int got = 0;
      check(MPI_Get_count(&status, MPI_BYTE, &got), "MPI_Get_count");
      if (got != receive_count)
        throw CommunicatorError("MpiCommunicator::send_receive: rank " + std::to_string(from) + " sent " +
                                std::to_string(got) + " bytes in chunk " + std::to_string(i) + " where " +
                                std::to_string(receive_count) + " were announced");
    }
  }
  if (!fits)
    throw CommunicatorError("MpiCommunicator::send_receive: rank " + std::to_string(from) + " sent " +
                            std::to_string(theirs) + " bytes; rank " + std::to_string(rank_) + " expected " +
                            std::to_string(receive.size()));
}

void MpiCommunicator::all_gather(std::span<const std::uint8_t> mine, std::span<std::uint8_t> all) {
  // Every rank's length and whether its `all` fits, so that every rank throws the same error.
  const std::uint64_t header[2] = {mine.size(), all.size() == mine.size() * std::size_t(size_) ? 1u : 0u};
  std::vector<std::uint64_t> headers(2 * std::size_t(size_));
  check(MPI_Allgather(header, 2, MPI_UINT64_T, headers.data(), 2, MPI_UINT64_T, comm_),
        "MpiCommunicator::all_gather: MPI_Allgather of the lengths");
  for (int r = 0; r < size_; ++r) {
    if (headers[2 * std::size_t(r)] != mine.size())
      throw CommunicatorError("MpiCommunicator::all_gather: rank " + std::to_string(r) + " passes " +
                              std::to_string(headers[2 * std::size_t(r)]) + " bytes, rank " + std::to_string(rank_) +
                              " passes " + std::to_string(mine.size()) + "; every rank must pass as many");
    if (headers[2 * std::size_t(r) + 1] == 0)
      throw CommunicatorError("MpiCommunicator::all_gather: rank " + std::to_string(r) + "'s output does not hold " +
                              std::to_string(size_) + " x " + std::to_string(mine.size()) + " bytes");
  }
  const std::size_t n = mine.size();
  if (n == 0) return;
  if (n <= chunk_bytes_) {
    check(MPI_Allgather(mine.data(), int(n), MPI_BYTE, all.data(), int(n), MPI_BYTE, comm_),
          "MpiCommunicator::all_gather: MPI_Allgather of " + std::to_string(n) + " bytes per rank");
    return;
  }
  // Chunk [at, at + len) of every rank's bytes lands at r * n + at: one element of len bytes whose
  // extent is n, so rank r's element starts r * n bytes after the chunk's place in rank 0's part.
  for (std::size_t at = 0; at < n; at += chunk_bytes_) {
    const int len = int(std::min(chunk_bytes_, n - at));
    MPI_Datatype bytes = MPI_DATATYPE_NULL, spaced = MPI_DATATYPE_NULL;
    check(MPI_Type_contiguous(len, MPI_BYTE, &bytes), "MPI_Type_contiguous");
    const int made = MPI_Type_create_resized(bytes, 0, MPI_Aint(n), &spaced);
    MPI_Type_free(&bytes);
    check(made, "MPI_Type_create_resized");
    int code = MPI_Type_commit(&spaced);
    if (code == MPI_SUCCESS) code = MPI_Allgather(mine.data() + at, len, MPI_BYTE, all.data() + at, 1, spaced, comm_);
    MPI_Type_free(&spaced);
    check(code, "MpiCommunicator::all_gather: MPI_Allgather of bytes " + std::to_string(at) + ".." +
                    std::to_string(at + std::size_t(len)) + " of " + std::to_string(n) + " per rank");
  }
}

bool MpiCommunicator::barrier_within(double seconds) {
  MPI_Request request = MPI_REQUEST_NULL;
  check(MPI_Ibarrier(comm_, &request), "MpiCommunicator::barrier_within: MPI_Ibarrier");
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    int done = 0;
    check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "MpiCommunicator::barrier_within: MPI_Test");
    if (done) return true;
    if (seconds >= 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds)
      return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void MpiCommunicator::abort(int status) {
  MPI_Abort(comm_, status);
  std::abort();  // MPI_Abort does not return; should it, this process ends anyway
}

}  // namespace granular
