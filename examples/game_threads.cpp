/// @file game_threads.cpp
/// A game that steps granular on its own threads: its job system (game_jobs.hpp) implements
/// granular::TaskSystem and goes in WorldDef::task_system, so every parallel loop of the CPU step
/// runs there and granular starts no threads to step. Exits non-zero unless the game's threads ran
/// the tasks and the world reached the hash of the same world on granular's own pool.

#include <granular/granular.hpp>

#include <cstdio>
#include <memory>

#include "game_jobs.hpp"

int main() {
  auto jobs = std::make_shared<game::GameJobs>(3);  // the game's job system, 3 worker threads
  granular::WorldDef def;
  def.size = {64, 64, 64};
  def.backend = granular::BackendKind::Cpu;
  def.task_system = jobs;                            // the CPU step runs on the game's threads
  granular::World world(def);
  world.paint(granular::Box{{16, 16, 30}, {48, 48, 50}}, granular::Material::Granular);
  world.step(60);

  granular::WorldDef own_def = def;                  // the same world on granular's own pool
  own_def.task_system = nullptr;
  own_def.threads = 2;
  granular::World own(own_def);
  own.paint(granular::Box{{16, 16, 30}, {48, 48, 50}}, granular::Material::Granular);
  own.step(60);

  const bool same = world.hash() == own.hash();
  std::printf("%s on the game's threads ran %llu tasks; hash %016llx, %s granular's own pool's\n",
              world.backend_description().c_str(), static_cast<unsigned long long>(jobs->tasks_run()),
              static_cast<unsigned long long>(world.hash()), same ? "equal to" : "DIFFERENT from");
  return same && jobs->tasks_run() > 0 ? 0 : 1;
}
