#include "cpu/thread_pool.hpp"

#include <string>
#include <system_error>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

#include "granular/errors.hpp"

namespace granular {

namespace {

/// Spins until `done()` or kThreadPoolSpin has passed; returns done().
template <class Done>
bool spin_until(Done&& done) {
  const auto until = std::chrono::steady_clock::now() + kThreadPoolSpin;
  for (;;) {
    for (int k = 0; k < 16; ++k) {
      if (done()) return true;
#if defined(__x86_64__) || defined(__i386__)
      _mm_pause();
#endif
    }
    std::this_thread::yield();  // a thread with work on this core goes first
    if (std::chrono::steady_clock::now() >= until) return done();
  }
}

}  // namespace

int hardware_threads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : int(n);
}

int max_threads() { return 4 * hardware_threads(); }

int resolve_threads(int threads, const char* field) {
  if (threads < 0 || threads > max_threads())
    throw InvalidArgument(std::string(field) + " = " + std::to_string(threads) + "; use 0 (all " +
                          std::to_string(hardware_threads()) + " hardware threads) or 1.." +
                          std::to_string(max_threads()) + " (4 times the hardware threads)");
  return threads == 0 ? hardware_threads() : threads;
}

ThreadPool::ThreadPool(int threads) {
  const int workers = threads > 1 ? threads - 1 : 0;
  try {
    workers_.reserve(std::size_t(workers));
    for (int i = 0; i < workers; ++i) workers_.emplace_back([this] { worker_loop(); });
  } catch (const std::exception& e) {
    const std::size_t started = workers_.size();
    stop_workers();
    throw BackendError("CPU thread pool: the system refused to start thread " + std::to_string(started + 2) +
                       " of " + std::to_string(threads) + " (" + e.what() +
                       "); use fewer threads (WorldDef::threads, --threads)");
  }
}

ThreadPool::~ThreadPool() { stop_workers(); }

void ThreadPool::stop_workers() noexcept {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  start_cv_.notify_all();
  for (auto& w : workers_) w.join();
  workers_.clear();
}

void ThreadPool::finish(int count) {
  const int tasks = tasks_.load(std::memory_order_relaxed);  // this job's: it has a task unfinished
  if (finished_.fetch_add(count, std::memory_order_acq_rel) + count == tasks) {
    std::lock_guard lock(mutex_);  // the caller tests finished_ under it before it sleeps
    done_cv_.notify_one();
  }
}

void ThreadPool::drain(std::uint32_t number) {
  constexpr std::uint64_t kTaskBits = 0xFFFFFFFFull;
  for (;;) {
    std::uint64_t next = next_.load(std::memory_order_acquire);
    do {
      // tasks_ is read with acquire: once it is the next job's, the close of this one that run()
      // stored before it is seen, and the exchange below fails.
      if (next >> 32 != number || (next & kTaskBits) >= std::uint64_t(tasks_.load(std::memory_order_acquire))) return;
    } while (!next_.compare_exchange_weak(next, next + 1, std::memory_order_acq_rel, std::memory_order_acquire));
    // The job cannot end before this task does, so job_ and tasks_ are this job's until then.
    const int task = int(next & kTaskBits), tasks = tasks_.load(std::memory_order_relaxed);
    try {
      (*job_)(task);
    } catch (...) {
      {
        std::lock_guard lock(mutex_);
        if (!error_) error_ = std::current_exception();
      }
      // No task is handed out after it: those left count as finished.
      std::uint64_t left = next_.load(std::memory_order_acquire);
      while (left >> 32 == number && int(left & kTaskBits) < tasks)
        if (next_.compare_exchange_weak(left, (left & ~kTaskBits) | std::uint64_t(tasks), std::memory_order_acq_rel,
                                        std::memory_order_acquire)) {
          finish(tasks - int(left & kTaskBits));
          break;
        }
    }
    finish(1);
  }
}

void ThreadPool::run(int tasks, const std::function<void(int)>& fn) {
  if (tasks <= 0) return;
  if (workers_.empty() || tasks == 1) {
    for (int t = 0; t < tasks; ++t) fn(t);
    return;
  }
  std::uint32_t number = 0;
  {
    std::lock_guard lock(mutex_);
    number = std::uint32_t(generation_.load(std::memory_order_relaxed) + 1);
    // Closed first, so that a thread still in drain() for the last job takes nothing once it sees
    // this job's count; opened once the job is set.
    next_.store(std::uint64_t(number) << 32 | 0xFFFFFFFFull, std::memory_order_release);
    job_ = &fn;
    tasks_.store(tasks, std::memory_order_release);
    finished_.store(0, std::memory_order_relaxed);
    error_ = nullptr;
    next_.store(std::uint64_t(number) << 32, std::memory_order_release);  // its tasks can be taken from here
    generation_.fetch_add(1, std::memory_order_release);                  // spinning workers start here
  }
  start_cv_.notify_all();  // sleeping ones here
  drain(number);
  auto done = [this, tasks] { return finished_.load(std::memory_order_acquire) == tasks; };
  spin_until(done);
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    done_cv_.wait(lock, done);
    job_ = nullptr;
    error = error_;
  }
  if (error) std::rethrow_exception(error);
}

void ThreadPool::worker_loop() {
  std::uint64_t seen = 0;
  for (;;) {
    auto job_or_stop = [&] {
      return stopping_.load(std::memory_order_acquire) || generation_.load(std::memory_order_acquire) != seen;
    };
    if (!spin_until(job_or_stop)) {
      std::unique_lock lock(mutex_);
      start_cv_.wait(lock, job_or_stop);
    }
    if (stopping_.load(std::memory_order_acquire)) return;
    seen = generation_.load(std::memory_order_acquire);
    drain(std::uint32_t(seen));
  }
}

}  // namespace granular
