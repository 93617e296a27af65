/// @file test_task_system.cpp
/// A World on the game's threads (WorldDef::task_system): every parallel loop of the CPU backend
/// runs on the game's task system, granular starts no thread of its own for it, and the result is
/// the result on granular's own pool. The game's task system is the one of examples/game_jobs.hpp.

#include <doctest/doctest.h>

#include <fstream>
#include <memory>
#include <string>

#include "../examples/game_jobs.hpp"
#include "granular/errors.hpp"
#include "granular/extend/threads.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;
using namespace granular::test;

namespace {

/// Threads of this process now (Linux: the Threads line of /proc/self/status); -1 elsewhere.
int process_threads() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key)
    if (key == "Threads:") {
      int n = -1;
      status >> n;
      return n;
    }
  return -1;
}

/// A task system that runs every task on the calling thread, one after another, and reports
/// `reported` as its thread count.
class SerialTasks final : public TaskSystem {
 public:
  explicit SerialTasks(int reported) : reported_(reported) {}
  void run(int count, const std::function<void(int)>& task) override {
    for (int i = 0; i < count; ++i) task(i);
  }
  int thread_count() const override { return reported_; }

 private:
  int reported_;
};

}  // namespace

TEST_CASE("task system: a world on the game's threads steps there and gets the hash of granular's own pool") {
  for (const char* rules : {"paper", "inertial-24"})
    for (const bool sparse : {true, false}) {
      CAPTURE(rules);
      CAPTURE(sparse);
      const Grid initial = random_grid({40, 36, 28}, 17, 8, 30);
      auto jobs = std::make_shared<game::GameJobs>(3);
      const int threads_before = process_threads();
      WorldDef own_def = test_def(initial.size(), rules, 3, 9);
      own_def.sparse = sparse;
      World own(own_def, initial);
      const int threads_with_own_pool = process_threads();
      WorldDef game_def = own_def;
      game_def.task_system = jobs;
      World game(game_def, initial);
      const int threads_with_game_world = process_threads();
      if (threads_before > 0) {
        // The own pool keeps 2 workers (3 threads, the caller included); the game's world none.
        CHECK(threads_with_own_pool == threads_before + 2);
        CHECK(threads_with_game_world == threads_with_own_pool);
      }
      CHECK(game.backend_description() == "cpu (3 threads)");

      for (const int ticks : {1, 7, 8, 20}) {
        const std::uint64_t before_step = jobs->tasks_run();
        own.step(ticks);
        game.step(ticks);
        CHECK(jobs->tasks_run() > before_step);  // the step's loops ran on the game's threads
        own.pour({20, 18, 20}, 3.0, Material::Granular, 30);
        game.pour({20, 18, 20}, 3.0, Material::Granular, 30);
        // count() runs thread_count() tasks and hash() 4 per thread, all on the game's threads.
        const std::uint64_t before_count = jobs->tasks_run();
        CHECK(game.count() == own.count());
        CHECK(jobs->tasks_run() == before_count + 3);
        CHECK(game.hash() == own.hash());
        CHECK(jobs->tasks_run() == before_count + 3 + 12);
      }
      CHECK(process_threads() == threads_with_game_world);
    }
}

TEST_CASE("task system: its thread count is bounded like WorldDef::threads") {
  WorldDef def = test_def({8, 8, 8});
  def.task_system = std::make_shared<SerialTasks>(0);
  check_has(error_of<InvalidArgument>([&] { World w(def); }), {"WorldDef::task_system->thread_count() = 0", "1.."});
  def.task_system = std::make_shared<SerialTasks>(max_threads() + 1);
  check_has(error_of<InvalidArgument>([&] { World w(def); }),
            {"WorldDef::task_system->thread_count() = " + std::to_string(max_threads() + 1)});
  def.task_system = std::make_shared<SerialTasks>(max_threads());
  World w(def);
  CHECK(w.backend_description() == "cpu (" + std::to_string(max_threads()) + " threads)");
}

TEST_CASE("task system: a serial one (every task on the caller) gives the pool's hash") {
  const Grid initial = random_grid({24, 24, 24}, 5);
  World own(test_def(initial.size(), "inertial-24", 2), initial);
  WorldDef def = test_def(initial.size(), "inertial-24", 2);
  def.task_system = std::make_shared<SerialTasks>(1);
  World serial(def, initial);
  own.step(30);
  serial.step(30);
  CHECK(serial.hash() == own.hash());
  CHECK(serial.backend_description() == "cpu (1 thread)");
}
