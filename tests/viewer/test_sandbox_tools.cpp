#include <doctest/doctest.h>

#include <memory>

#include "granular/raycast.hpp"
#include "sandbox_tools.hpp"
#include "granular/world.hpp"
#include "viewer_test_support.hpp"

using namespace viewer;

TEST_CASE("tools: a held brush acts once per fixed update at the picked point; released, nothing") {
  // A floor with a layer of sand on it, and room above.
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {32, 32, 32};
  auto world = std::make_unique<granular::World>(def);
  world->paint(granular::Box{{0, 0, 0}, {32, 32, 2}}, granular::Material::Solid);
  world->paint(granular::Box{{0, 0, 2}, {32, 32, 8}}, granular::Material::Granular);
  ToolSubsystem tools(*world, {});
  const auto hit = granular::raycast(*world, {16.5, 16.5, 100.0}, {0, 0, -1});
  REQUIRE(hit);
  ToolState& state = tools.state();
  state.target = hit->point;
  state.radius = 3.0;

  state.tool = Tool::Dig;
  const auto before = world->count();
  tools.fixed_update(1.0 / 60);
  CHECK(world->count()[2] == before[2]);  // not held: nothing happens
  state.held = true;
  tools.fixed_update(1.0 / 60);
  const auto dug = world->count();
  CHECK(dug[2] < before[2]);
  CHECK(dug[1] == before[1]);  // digging never removes solid

  state.tool = Tool::Pour;
  state.pour_per_tick = 10;
  tools.fixed_update(1.0 / 60);
  tools.fixed_update(1.0 / 60);
  CHECK(world->count()[2] == dug[2] + 20);  // a steady rate: 10 cells per fixed update

  state.material = granular::Material::Liquid;  // the chosen material is what Pour emits
  tools.fixed_update(1.0 / 60);
  CHECK(world->count()[3] == 10);

  state.tool = Tool::Place;  // paints the chosen material: a static one builds structure
  state.material = granular::Material::Solid;
  state.target_in_front = granular::Vec3{16.5, 16.5, 20.5};
  tools.fixed_update(1.0 / 60);
  const auto placed = world->count();
  CHECK(placed[1] > dug[1]);
  state.material = granular::Material::State6;
  state.target_in_front = granular::Vec3{8.5, 8.5, 20.5};
  tools.fixed_update(1.0 / 60);
  CHECK(world->count()[6] > 0);
  state.tool = Tool::Erase;
  state.target = granular::Vec3{16.5, 16.5, 20.5};
  tools.fixed_update(1.0 / 60);
  CHECK(world->count()[1] < placed[1]);
  CHECK(tools.cells_changed() > 0);
}

TEST_CASE("tools: apply_once applies the tool a single time, held or not (a click between two fixed updates)") {
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {32, 32, 32};
  granular::World world(def);
  world.paint(granular::Box{{0, 0, 0}, {32, 32, 8}}, granular::Material::Granular);
  ToolSubsystem tools(world, {});
  tools.state().tool = Tool::Dig;
  tools.state().radius = 3.0;
  tools.state().target = granular::Vec3{16.5, 16.5, 8.0};
  const auto before = world.count()[2];
  tools.apply_once();
  CHECK(tools.applications() == 1);
  CHECK_FALSE(tools.state().held);
  CHECK(tools.cells_changed() > 0);
  CHECK(world.count()[2] == before - std::uint64_t(tools.cells_changed()));
  tools.fixed_update(1.0 / 60);  // not held: a fixed update applies nothing
  CHECK(tools.applications() == 1);
}
