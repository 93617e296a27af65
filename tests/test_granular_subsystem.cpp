// Tests of GranularSubsystem (engine/, target granular::engine_granular): a granular::World
// stepped by the EngineLoop, driven by ManualClock.

#include <doctest/doctest.h>

#include <stdexcept>

#include "engine/clock.hpp"
#include "engine/engine_loop.hpp"
#include "engine/granular_subsystem.hpp"
#include "granular/geometry.hpp"
#include "granular/material.hpp"
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

  engine::ManualClock clock;
  engine::EngineLoop loop(clock);  // 60 Hz
  engine::GranularSubsystem sand(world, 2);
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

TEST_CASE("GranularSubsystem rejects ticks_per_fixed_update < 1") {
  granular::World world = make_world();
  CHECK_THROWS_AS(engine::GranularSubsystem(world, 0), std::invalid_argument);
  CHECK_THROWS_AS(engine::GranularSubsystem(world, -2), std::invalid_argument);
  engine::GranularSubsystem sand(world, 1);
  CHECK_THROWS_AS(sand.set_ticks_per_fixed_update(0), std::invalid_argument);
  CHECK(sand.ticks_per_fixed_update() == 1);
}
