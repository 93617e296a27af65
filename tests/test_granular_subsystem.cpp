// Tests of GranularSubsystem (engine/, target granular::engine_granular): a granular::World
// stepped by the EngineLoop, driven by ManualClock.

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "granular/engine/clock.hpp"
#include "granular/engine/engine_loop.hpp"
#include "granular/engine/granular_subsystem.hpp"
#include "granular/geometry.hpp"
#include "granular/material.hpp"
#include "granular/time_scale.hpp"
#include "granular/world.hpp"
#include "granular/world_def.hpp"

namespace {

/// A 16^3 world with a 8 x 8 x 4 slab of sand floating at z = 10..13.
granular::World make_world() {
  granular::WorldDef def;
  def.size = {16, 16, 16};
  granular::World world(def);
  world.paint(granular::Box{{4, 4, 10}, {12, 12, 14}}, granular::Material::Granular);
  return world;
}

std::uint64_t grains(const granular::World& world) {
  return world.count()[granular::to_cell(granular::Material::Granular)];
}

}  // namespace

TEST_CASE("GranularSubsystem steps the world ticks_per_fixed_update ticks per fixed tick") {
  granular::World world = make_world();
  const std::uint64_t grains_before = grains(world);
  REQUIRE(grains_before == 8 * 8 * 4);
  const std::uint64_t hash_before = world.hash();
  REQUIRE(world.tick() == 0);

  granular::engine::ManualClock clock;
  granular::engine::EngineLoop loop(clock);  // 60 Hz
  granular::engine::GranularSubsystem sand(world, 2);
  CHECK(sand.name() == "granular");
  CHECK(sand.ticks_per_fixed_update() == 2);
  CHECK(&sand.world() == &world);
  loop.add(sand);

  loop.run_frame();  // first frame: zero delta, no tick
  CHECK(world.tick() == 0);
  CHECK(sand.last_step_seconds() == 0.0);

  for (int i = 0; i < 5; ++i) {
    clock.advance(1.0 / 60.0);
    CHECK(loop.run_frame().ticks == 1);
  }
  clock.advance(3.0 / 60.0);
  CHECK(loop.run_frame().ticks == 3);

  CHECK(loop.stats().ticks == 8);
  CHECK(sand.fixed_updates() == 8);
  CHECK(world.tick() == 2 * loop.stats().ticks);
  CHECK(world.tick() == 16);
  CHECK(grains(world) == grains_before);
  CHECK(world.hash() != hash_before);  // the slab falls under gravity
  CHECK(sand.last_step_seconds() >= 0.0);
  CHECK(sand.total_step_seconds() >= sand.last_step_seconds());

  sand.set_ticks_per_fixed_update(3);
  clock.advance(2.0 / 60.0);
  CHECK(loop.run_frame().ticks == 2);
  CHECK(world.tick() == 16 + 2 * 3);
  CHECK(grains(world) == grains_before);
}

TEST_CASE("GranularSubsystem rejects a fixed tick count < 1 and a bad def") {
  granular::World world = make_world();
  CHECK_THROWS_AS(granular::engine::GranularSubsystem(world, 0), std::invalid_argument);
  CHECK_THROWS_AS(granular::engine::GranularSubsystem(world, -2), std::invalid_argument);
  granular::engine::GranularSubsystem sand(world, 1);
  CHECK_THROWS_AS(sand.set_ticks_per_fixed_update(-1), std::invalid_argument);
  CHECK(sand.ticks_per_fixed_update() == 1);
  CHECK_THROWS_AS(sand.set_time_scale(0.0), std::invalid_argument);
  CHECK_THROWS_AS(sand.set_time_scale(std::nan("")), std::invalid_argument);
  CHECK_THROWS_AS(sand.request_step(0), std::invalid_argument);
  granular::engine::GranularSubsystemDef def;
  def.max_ticks_per_update = 0;
  CHECK_THROWS_WITH_AS(granular::engine::GranularSubsystem(world, def), doctest::Contains("max_ticks_per_update = 0"),
                       std::invalid_argument);
}

TEST_CASE("GranularSubsystem steps at the rules' real-time rate by default, whatever the loop's rate") {
  granular::World world = make_world();
  const double tick = granular::tick_seconds(world.rules());
  REQUIRE(tick > 1.0 / 60.0);  // the default rules' tick is longer than a 60 Hz update
  granular::engine::ManualClock clock;
  granular::engine::EngineLoop loop(clock);  // 60 Hz
  granular::engine::GranularSubsystem sand(world);
  CHECK(sand.ticks_per_fixed_update() == 0);
  CHECK(sand.tick_seconds() == tick);
  loop.add(sand);
  loop.run_frame();
  for (int i = 0; i < 120; ++i) {  // two seconds of loop time
    clock.advance(1.0 / 60.0);
    loop.run_frame();
  }
  // One world tick per tick_seconds of loop time: the sand falls at the speed of real sand.
  const double loop_seconds = double(loop.stats().ticks) * loop.timestep().tick_seconds();
  CHECK(world.tick() == std::uint64_t(std::floor(loop_seconds / tick + 1e-9)));
  CHECK(sand.simulated_seconds() <= loop_seconds + 1e-9);
  CHECK(sand.simulated_seconds() > loop_seconds - tick);

  // Twice the time scale, twice the ticks.
  const std::uint64_t at = world.tick();
  sand.set_time_scale(2.0);
  for (int i = 0; i < 120; ++i) {
    clock.advance(1.0 / 60.0);
    loop.run_frame();
  }
  CHECK(std::llabs(std::int64_t(world.tick() - at) - std::int64_t(std::llround(4.0 / tick))) <= 1);
}

TEST_CASE("GranularSubsystem drops time owed past max_ticks_per_update") {
  granular::World world = make_world();
  granular::engine::GranularSubsystemDef def;
  def.max_ticks_per_update = 2;
  granular::engine::GranularSubsystem sand(world, def);
  sand.fixed_update(10 * sand.tick_seconds() + 0.25 * sand.tick_seconds());
  CHECK(sand.last_update_ticks() == 2);
  CHECK(world.tick() == 2);
  CHECK(sand.dropped_seconds() == doctest::Approx(8 * sand.tick_seconds()));
  sand.fixed_update(0.75 * sand.tick_seconds());  // the fraction was kept
  CHECK(sand.last_update_ticks() == 1);
}

TEST_CASE("GranularSubsystem pauses and single-steps") {
  granular::World world = make_world();
  granular::engine::GranularSubsystem sand(world);
  sand.set_paused(true);
  CHECK(sand.paused());
  for (int i = 0; i < 10; ++i) sand.fixed_update(1.0);
  CHECK(world.tick() == 0);
  CHECK(sand.fixed_updates() == 10);
  sand.request_step(3);
  sand.fixed_update(1.0 / 60.0);
  CHECK(world.tick() == 3);
  sand.fixed_update(1.0 / 60.0);
  CHECK(world.tick() == 3);
  sand.set_paused(false);  // paused time is not owed afterwards
  sand.fixed_update(0.5 * sand.tick_seconds());
  CHECK(world.tick() == 3);
  sand.fixed_update(0.5 * sand.tick_seconds());
  CHECK(world.tick() == 4);
}

TEST_CASE("GranularSubsystem runs its ticks through a stepper, and checks it ran them all") {
  granular::World world = make_world();
  granular::engine::GranularSubsystem sand(world, 3);
  std::vector<int> asked;
  sand.set_stepper([&](int ticks) {
    asked.push_back(ticks);
    for (int i = 0; i < ticks; ++i) world.step(1);  // a tick at a time, as a physics engine in lockstep
  });
  sand.fixed_update(1.0 / 60.0);
  sand.set_paused(true);
  sand.fixed_update(1.0 / 60.0);  // paused: the stepper is not called
  sand.request_step(2);
  sand.fixed_update(1.0 / 60.0);
  CHECK(asked == std::vector<int>{3, 2});
  CHECK(world.tick() == 5);
  CHECK(sand.simulated_seconds() == doctest::Approx(5 * sand.tick_seconds()));

  sand.set_stepper([&](int) { world.step(1); });  // one tick short of what an update owes
  sand.request_step(2);
  CHECK_THROWS_WITH_AS(sand.fixed_update(1.0 / 60.0), doctest::Contains("not 2 ticks"), std::logic_error);

  sand.set_stepper({});  // World::step again
  sand.request_step(2);
  sand.fixed_update(1.0 / 60.0);
  CHECK(world.tick() == 8);
}
