#include <doctest/doctest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "granular/raycast.hpp"
#include "granular/rule_presets.hpp"
#include "session/sandbox_tools.hpp"
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

TEST_CASE("tools: Tab offers shake only under rules with a motion model, at their highest level") {
  for (const char* name : {"inertial", "inertial-24"}) {
    CAPTURE(name);
    const granular::RuleSet rules = granular::preset(name);
    CHECK(shake_level(rules) == rules.motion.max_level());
    CHECK(left_button_tools(rules) == std::vector<Tool>{Tool::Dig, Tool::Erase, Tool::Shake});
    CHECK(next_left_tool(Tool::Dig, rules) == Tool::Erase);
    CHECK(next_left_tool(Tool::Erase, rules) == Tool::Shake);
    CHECK(next_left_tool(Tool::Shake, rules) == Tool::Dig);
  }
  CHECK(shake_level(granular::preset("inertial-24")) == 12);
  for (const char* name : {"paper", "isotropic", "d4"}) {
    CAPTURE(name);
    const granular::RuleSet rules = granular::preset(name);
    CHECK(shake_level(rules) == 0);
    CHECK(left_button_tools(rules) == std::vector<Tool>{Tool::Dig, Tool::Erase});
    CHECK(next_left_tool(Tool::Dig, rules) == Tool::Erase);
    CHECK(next_left_tool(Tool::Erase, rules) == Tool::Dig);
    CHECK(next_left_tool(Tool::Shake, rules) == Tool::Dig);  // left over from other rules: back to dig
  }
}

TEST_CASE("tools: shake sets the grains at the brush moving, so a resting slope slides; under one-step rules it does nothing") {
  // A column of sand collapsed into a pile at rest, shaken on its flank, against a twin left alone.
  auto pile = [](const char* rules) {
    granular::WorldDef def;
    def.backend = granular::BackendKind::Cpu;
    def.size = {32, 32, 32};
    def.rules = rules;
    auto world = std::make_unique<granular::World>(def);
    world->paint(granular::Box{{0, 0, 0}, {32, 32, 2}}, granular::Material::Solid);
    world->paint(granular::Box{{13, 13, 2}, {19, 19, 28}}, granular::Material::Granular);
    world->step(400);
    return world;
  };
  auto shaken = pile("inertial-24");
  auto still = pile("inertial-24");
  REQUIRE(shaken->hash() == still->hash());
  const granular::Grid rest = shaken->read_grid();
  const auto counts = shaken->count();
  ToolSubsystem tools(*shaken, {});
  tools.state().tool = Tool::Shake;
  tools.state().radius = 4.0;
  tools.state().target = granular::Vec3{16.0, 16.0, 6.0};
  tools.apply_once();
  CHECK(tools.cells_changed() > 0);  // the cells set moving
  CHECK(shaken->count() == counts);  // no material changes
  CHECK(shaken->hash() != still->hash());
  shaken->step(60);
  still->step(60);
  auto cells_moved = [&](const granular::World& world) {
    const granular::Grid now = world.read_grid();
    std::int64_t moved = 0;
    for (std::size_t i = 0; i < rest.cells().size(); ++i) moved += rest.cells()[i] != now.cells()[i];
    return moved;
  };
  MESSAGE(tools.cells_changed() << " cells set moving; after 60 ticks " << cells_moved(*shaken)
                                 << " cells differ from the resting pile");
  CHECK(cells_moved(*still) == 0);  // at rest, the twin stays as it was
  CHECK(cells_moved(*shaken) > 0);  // shaken, sand slid down the pile

  auto paper = pile("paper");
  const std::uint64_t before = paper->hash();
  ToolState state;
  state.tool = Tool::Shake;
  state.held = true;
  state.target = granular::Vec3{16.0, 16.0, 6.0};
  std::int64_t changed = -1;
  CHECK_NOTHROW(changed = apply_tool(*paper, state));
  CHECK(changed == 0);
  CHECK(paper->hash() == before);
}
