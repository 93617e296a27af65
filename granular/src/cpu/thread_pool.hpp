#pragma once
/// @file thread_pool.hpp
/// granular's own task system (task_system.hpp): a fixed set of worker threads that run
/// index-parallel jobs, the calling thread taking part.

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>
#include <atomic>

#include "granular/task_system.hpp"
#include "granular/extend/threads.hpp"

namespace granular {

/// Runs `fn(task)` for task in [0, tasks) across `thread_count()` threads (workers plus the
/// caller) and returns when all are done. Tasks must be independent; which thread runs which task
/// is not fixed, so results must not depend on it.
class ThreadPool final : public TaskSystem {
 public:
  /// A pool of `threads` threads in total (>= 1); `threads - 1` workers are started. Throws
  /// BackendError naming the thread when the system refuses to start one (the workers already
  /// started are stopped and joined first).
  explicit ThreadPool(int threads);
  ~ThreadPool() override;
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  /// Total threads, the caller included.
  int thread_count() const override { return int(workers_.size()) + 1; }
  /// Runs the tasks and waits. An exception from a task is rethrown here (the first one).
  void run(int tasks, const std::function<void(int)>& fn) override;

 private:
  void worker_loop();
  void drain();
  void stop_workers() noexcept;

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_cv_;
  std::condition_variable done_cv_;
  std::uint64_t generation_ = 0;
  bool stopping_ = false;
  const std::function<void(int)>* job_ = nullptr;
  int tasks_ = 0;
  std::atomic<int> next_{0};
  int busy_workers_ = 0;
  std::exception_ptr error_;
};

}  // namespace granular
