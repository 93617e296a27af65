#include "granular/distributed/local_group.hpp"

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "granular/errors.hpp"

namespace granular {

/// The mailboxes: one queue of messages per (sender, receiver) pair, and the failure, if any.
struct LocalGroup::Shared {
  int size = 0;
  std::mutex mutex;
  std::condition_variable arrived;
  std::vector<std::deque<std::vector<std::uint8_t>>> boxes;  ///< [from * size + to]
  std::string failure;                                        ///< why the group failed; empty while it has not
  std::vector<std::vector<std::uint8_t>> spare;                ///< delivered messages' buffers, for reuse
  std::vector<std::unique_ptr<RankCommunicator>> ranks;

  // Posting never fails, even in a failed group: a rank that has an error of its own and tells the
  // others (all_true) must get to throw it.
  void post(int from, int to, std::span<const std::uint8_t> bytes) {
    std::vector<std::uint8_t> message = spare_buffer();
    message.assign(bytes.begin(), bytes.end());
    {
      const std::lock_guard lock(mutex);
      boxes[std::size_t(from) * std::size_t(size) + std::size_t(to)].push_back(std::move(message));
    }
    arrived.notify_all();
  }

  void take(int from, int to, std::span<std::uint8_t> out) {
    std::unique_lock lock(mutex);
    auto& box = boxes[std::size_t(from) * std::size_t(size) + std::size_t(to)];
    arrived.wait(lock, [&] { return !box.empty() || !failure.empty(); });
    if (box.empty()) throw_if_failed();  // a message sent before the failure is still delivered
    std::vector<std::uint8_t> message = std::move(box.front());
    box.pop_front();
    lock.unlock();
    if (message.size() != out.size())
      throw CommunicatorError("in-process rank " + std::to_string(to) + " expected " + std::to_string(out.size()) +
                              " bytes from rank " + std::to_string(from) + " and got " + std::to_string(message.size()) +
                              " (the ranks called different operations)");
    std::copy(message.begin(), message.end(), out.begin());
    const std::lock_guard relock(mutex);
    spare.push_back(std::move(message));
  }

  // A message buffer delivered before, whose memory a new message reuses (a halo is megabytes).
  std::vector<std::uint8_t> spare_buffer() {
    const std::lock_guard lock(mutex);
    if (spare.empty()) return {};
    std::vector<std::uint8_t> b = std::move(spare.back());
    spare.pop_back();
    return b;
  }

  void throw_if_failed() const {
    if (!failure.empty()) throw CommunicatorError(failure);
  }
};

/// One rank's Communicator over the shared mailboxes.
class LocalGroup::RankCommunicator final : public Communicator {
 public:
  RankCommunicator(Shared& shared, int rank) : shared_(shared), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return shared_.size; }
  std::string description() const override {
    return "in-process, " + std::to_string(shared_.size) + (shared_.size == 1 ? " rank" : " ranks");
  }
  void send_receive(int to, std::span<const std::uint8_t> send, int from, std::span<std::uint8_t> receive) override {
    check_rank(to, "to");
    check_rank(from, "from");
    if (to != kNoRank) shared_.post(rank_, to, send);
    if (from != kNoRank) shared_.take(from, rank_, receive);
  }
  void all_gather(std::span<const std::uint8_t> mine, std::span<std::uint8_t> all) override {
    const std::size_t n = mine.size();
    if (all.size() != n * std::size_t(shared_.size))
      throw CommunicatorError("all_gather: " + std::to_string(all.size()) + " bytes of room for " +
                              std::to_string(shared_.size) + " ranks of " + std::to_string(n));
    for (int r = 0; r < shared_.size; ++r)
      if (r != rank_) shared_.post(rank_, r, mine);
    std::copy(mine.begin(), mine.end(), all.begin() + std::ptrdiff_t(std::size_t(rank_) * n));
    for (int r = 0; r < shared_.size; ++r)
      if (r != rank_) shared_.take(r, rank_, all.subspan(std::size_t(r) * n, n));
  }

 private:
  void check_rank(int r, const char* what) const {
    if (r != kNoRank && (r < 0 || r >= shared_.size))
      throw CommunicatorError(std::string("send_receive: ") + what + " = " + std::to_string(r) + " is not a rank of " +
                              description());
  }
  Shared& shared_;
  int rank_;
};

LocalGroup::LocalGroup(int size) : shared_(std::make_unique<Shared>()) {
  if (size < 1 || size > 4096)
    throw InvalidArgument("LocalGroup: size = " + std::to_string(size) + "; use 1..4096 ranks");
  shared_->size = size;
  shared_->boxes.resize(std::size_t(size) * std::size_t(size));
  for (int r = 0; r < size; ++r) shared_->ranks.push_back(std::make_unique<RankCommunicator>(*shared_, r));
}

LocalGroup::~LocalGroup() = default;

int LocalGroup::size() const { return shared_->size; }

Communicator& LocalGroup::rank(int r) {
  if (r < 0 || r >= shared_->size)
    throw InvalidArgument("LocalGroup::rank: r = " + std::to_string(r) + " is outside 0.." + std::to_string(shared_->size - 1));
  return *shared_->ranks[std::size_t(r)];
}

void LocalGroup::fail(int r, const std::string& why) {
  {
    const std::lock_guard lock(shared_->mutex);
    if (shared_->failure.empty()) shared_->failure = "in-process rank " + std::to_string(r) + " failed: " + why;
  }
  shared_->arrived.notify_all();
}

void run_local_ranks(int ranks, const std::function<void(Communicator&)>& fn) {
  LocalGroup group(ranks);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(ranks));
  {
    std::vector<std::jthread> threads;
    threads.reserve(std::size_t(ranks));
    for (int r = 0; r < ranks; ++r)
      threads.emplace_back([&, r] {
        try {
          fn(group.rank(r));
        } catch (const std::exception& e) {
          errors[std::size_t(r)] = std::current_exception();
          group.fail(r, e.what());
        } catch (...) {
          errors[std::size_t(r)] = std::current_exception();
          group.fail(r, "an exception that is not a std::exception");
        }
      });
  }
  // The first rank that failed on its own, not one that stopped because another did.
  for (const std::exception_ptr& e : errors) {
    if (!e) continue;
    try {
      std::rethrow_exception(e);
    } catch (const CommunicatorError&) {
      continue;
    } catch (...) {
      throw;
    }
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace granular
