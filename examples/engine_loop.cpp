/// @file engine_loop.cpp
/// A game loop around granular: the engine's fixed-timestep loop on the real clock, with the
/// subsystem that steps a world at its rules' real-time rate. Runs two seconds of simulated sand
/// in two seconds of wall time and exits non-zero if sand was created or destroyed.

#include <granular/engine/clock.hpp>
#include <granular/engine/engine_loop.hpp>
#include <granular/engine/granular_subsystem.hpp>
#include <granular/granular.hpp>

#include <cstdio>

int main() {
  granular::WorldDef def;
  def.size = {64, 64, 64};
  granular::World world(def);
  world.paint(granular::Box{{0, 0, 0}, {64, 64, 2}}, granular::Material::Solid);
  world.paint(granular::Box{{16, 16, 40}, {48, 48, 60}}, granular::Material::Granular);
  const auto before = world.count();

  granular::engine::SteadyClock clock;                // the real clock
  granular::engine::EngineLoop loop(clock);           // fixed updates at 60 Hz
  granular::engine::GranularSubsystem sand(world);    // steps the world at its rules' real-time rate
  loop.add(sand);                                     // your own subsystems go beside it
  loop.run([&] { return sand.simulated_seconds() < 2.0; });  // until the game quits

  std::printf("frames %llu, fixed updates %llu, ticks %llu (%.3f simulated s, %.3f ms per tick), mass %s\n",
              static_cast<unsigned long long>(loop.stats().frames), static_cast<unsigned long long>(loop.stats().ticks),
              static_cast<unsigned long long>(world.tick()), sand.simulated_seconds(),
              world.tick() ? sand.total_step_seconds() * 1e3 / double(world.tick()) : 0.0,
              world.count() == before ? "conserved" : "NOT conserved");
  return world.count() == before ? 0 : 1;
}
