#pragma once
/// @file game_jobs.hpp
/// A game's job system, as small as one can be: a fixed set of worker threads that run the tasks of
/// one batch at a time. It implements granular::TaskSystem, so a World steps its CPU backend on
/// these threads (WorldDef::task_system); a game passes its own job system the same way (Box2D's
/// enqueueTask/finishTask or Jolt's JobSystem behind the two methods).

#include <granular/task_system.hpp>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace game {

/// Worker threads that run granular's parallel loops; the thread that calls run() only waits. One
/// batch at a time: worlds that share it are stepped from one thread.
class GameJobs final : public granular::TaskSystem {
 public:
  /// Starts `workers` threads (at least 1).
  explicit GameJobs(int workers) {
    for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { work(); });
  }
  ~GameJobs() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    for (auto& t : threads_) t.join();
  }
  GameJobs(const GameJobs&) = delete;
  GameJobs& operator=(const GameJobs&) = delete;

  /// Hands the tasks to the workers and waits until all have run; rethrows a task's exception.
  void run(int count, const std::function<void(int)>& task) override {
    std::unique_lock lock(mutex_);
    task_ = &task;
    count_ = count;
    next_ = 0;
    finished_ = 0;
    wake_.notify_all();
    done_.wait(lock, [&] { return finished_ == count_; });
    task_ = nullptr;
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }
  /// The worker threads.
  int thread_count() const override { return int(threads_.size()); }

  /// Tasks the workers have run so far.
  std::uint64_t tasks_run() const { return tasks_run_.load(); }

 private:
  void work() {
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stopping_ || (task_ != nullptr && next_ < count_); });
      if (stopping_) return;
      const std::function<void(int)>& task = *task_;
      const int index = next_++;
      lock.unlock();
      std::exception_ptr error;
      try {
        task(index);
      } catch (...) {
        error = std::current_exception();
      }
      tasks_run_.fetch_add(1);
      lock.lock();
      if (error && !error_) error_ = error;
      if (++finished_ == count_) done_.notify_all();
    }
  }

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_;  ///< a batch was handed out, or stopping_
  std::condition_variable done_;  ///< the batch's last task finished
  const std::function<void(int)>* task_ = nullptr;  ///< the batch being run, null between batches
  int count_ = 0;
  int next_ = 0;      ///< the next task index to hand out
  int finished_ = 0;  ///< tasks of the batch that have finished
  std::exception_ptr error_;
  bool stopping_ = false;
  std::atomic<std::uint64_t> tasks_run_{0};
};

}  // namespace game
