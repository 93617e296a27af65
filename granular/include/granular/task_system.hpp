#pragma once
/// @file task_system.hpp
/// The threads the CPU backend runs on. By default a World starts its own pool of WorldDef::threads
/// threads; a game with a job system of its own (Box2D's enqueueTask/finishTask, Jolt's JobSystem)
/// implements TaskSystem and passes it as WorldDef::task_system, so every parallel loop of the CPU
/// step runs on the game's threads and granular starts none for stepping.

#include <functional>

namespace granular {

/// Runs batches of independent tasks in parallel: the parallel-for the CPU backend is built on.
/// granular calls run() from the thread that calls World (one call at a time per World; worlds
/// sharing one TaskSystem may call it from their own threads at once).
class TaskSystem {
 public:
  virtual ~TaskSystem() = default;

  /// Runs `task(i)` once for every i in [0, count) and returns when all have finished. The tasks
  /// are independent (any order, any thread, any number at once gives the same result); the caller
  /// may run some of them itself. An exception thrown by a task must be rethrown by run() after
  /// every task has finished. count >= 0; run(0, ...) returns at once.
  virtual void run(int count, const std::function<void(int)>& task) = 0;

  /// How many tasks may run at once (1 or more, at most max_threads(), threads.hpp): granular
  /// splits its loops into a few times this many tasks, so uneven tasks still balance.
  virtual int thread_count() const = 0;
};

}  // namespace granular
