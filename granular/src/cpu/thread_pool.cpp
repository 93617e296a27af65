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

void ThreadPool::drain() {
  for (;;) {
    const int task = next_.fetch_add(1, std::memory_order_relaxed);
    if (task >= tasks_) return;
    try {
      (*job_)(task);
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
      next_.store(tasks_, std::memory_order_relaxed);  // stop handing out tasks
    }
  }
}

void ThreadPool::run(int tasks, const std::function<void(int)>& fn) {
  if (tasks <= 0) return;
  if (workers_.empty() || tasks == 1) {
    for (int t = 0; t < tasks; ++t) fn(t);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    job_ = &fn;
    tasks_ = tasks;
    next_.store(0, std::memory_order_relaxed);
    busy_workers_.store(int(workers_.size()), std::memory_order_relaxed);
    error_ = nullptr;
    generation_.fetch_add(1, std::memory_order_release);  // spinning workers start here
  }
  start_cv_.notify_all();  // sleeping ones here
  drain();
  std::exception_ptr error;
  spin_until([this] { return busy_workers_.load(std::memory_order_acquire) == 0; });
  {
    std::unique_lock lock(mutex_);
    done_cv_.wait(lock, [this] { return busy_workers_.load(std::memory_order_acquire) == 0; });
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
    drain();
    if (busy_workers_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard lock(mutex_);  // the caller tests busy_workers_ under it before it sleeps
      done_cv_.notify_one();
    }
  }
}

}  // namespace granular
