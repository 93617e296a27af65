#pragma once
/// @file thread_pool.hpp
/// granular's own task system (task_system.hpp): a fixed set of worker threads that run
/// index-parallel jobs, the calling thread taking part. Between jobs a worker spins for
/// kThreadPoolSpin before it sleeps, so that the jobs of one tick, a few to a few hundred
/// microseconds apart, do not each pay for waking the workers. A job is done when its tasks are:
/// the caller does not wait for workers still waking, which take what tasks are left, if any.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "granular/task_system.hpp"
#include "granular/extend/threads.hpp"

namespace granular {

/// How long a worker that finished a job, and a caller waiting for its tasks, spin before they
/// sleep: longer than the gaps between the jobs of one tick, short against a tick's frame.
inline constexpr std::chrono::microseconds kThreadPoolSpin{200};

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
  // Runs tasks of job `number` (the low 32 bits of generation_) until none is left to take.
  void drain(std::uint32_t number);
  // Counts `count` tasks of the job finished; the last wakes the caller.
  void finish(int count);
  void stop_workers() noexcept;

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_cv_;
  std::condition_variable done_cv_;
  std::atomic<std::uint64_t> generation_{0};  ///< the job's number; written under mutex_
  std::atomic<bool> stopping_{false};         ///< written under mutex_
  /// The job's number (high 32 bits) and its next task to take (low 32): a thread takes a task by
  /// raising it while the number is still its job's, so it never takes one of a later job.
  std::atomic<std::uint64_t> next_{0};
  const std::function<void(int)>* job_ = nullptr;  ///< read only by a thread that took a task
  std::atomic<int> tasks_{0};
  std::atomic<int> finished_{0};  ///< tasks of the job finished, or skipped after an exception
  std::exception_ptr error_;      ///< written under mutex_
};

}  // namespace granular
