#include <doctest/doctest.h>

#include <memory>

#include "granular/errors.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world.hpp"

using namespace granular;

namespace {

/// A column of `material` cells in the middle of a void 8x8x8 world with a solid floor, stepped
/// `ticks` ticks under `rules`; returns how many of them lie on the floor layer above it.
std::uint64_t settled_on_floor(std::shared_ptr<const RuleSet> rules, std::uint8_t material, int ticks) {
  WorldDef def;
  def.size = {8, 8, 8};
  def.backend = BackendKind::Cpu;
  def.threads = 1;
  def.rule_set = std::move(rules);
  World world(def);
  world.paint(Box{{0, 0, 0}, {8, 8, 1}}, Material::Solid);
  world.paint(Box{{3, 3, 4}, {5, 5, 8}}, Material(material));
  world.step(ticks);
  const auto layer = world.read_region(Box{{0, 0, 1}, {8, 8, 2}});
  std::uint64_t n = 0;
  for (auto c : layer) n += c == material;
  return n;
}

}  // namespace

TEST_CASE("rule set: a preset is a value whose material table a game may change") {
  const RuleSet paper = preset("paper");
  CHECK(paper.materials[0].behaviour == Behaviour::Void);
  CHECK(paper.materials[1].behaviour == Behaviour::Static);
  CHECK(paper.materials[2].behaviour == Behaviour::Granular);
  CHECK(paper.materials[2].name == "granular");
  CHECK(paper.materials[3].behaviour == Behaviour::Liquid);
  CHECK(paper.materials[4].behaviour == Behaviour::Gas);
  CHECK(paper.materials[5].behaviour == Behaviour::Granular);
  CHECK(paper.materials[5].name == "gravel");
  CHECK(paper.materials[6].behaviour == Behaviour::Static);
  CHECK(paper.materials[7].behaviour == Behaviour::Static);
  // Density order: gas < void < liquid < sand < gravel.
  CHECK(paper.materials[4].density < 0);
  CHECK(paper.materials[0].density == 0);
  CHECK(paper.materials[3].density < paper.materials[2].density);
  CHECK(paper.materials[2].density < paper.materials[5].density);
  const RuleSet inertial = preset("inertial-24");
  CHECK(inertial.motion.substeps == 24);
  CHECK(inertial.materials[2].grain.roll_cost == 160);
  CHECK_FALSE(inertial.motion.columns);
  const RuleSet columns = preset("inertial-24-columns");
  CHECK(columns.motion.columns);
  CHECK(columns.motion.substeps == 24);
  CHECK(columns.materials[2].grain.flow_level == 1);  // the default's grain: a pile flows as under the default
  CHECK(columns.materials[2].grain.entrain == 128);
  CHECK(inertial.materials[2].grain.entrain == 0);
  const RuleSet entrain = preset("inertial-24-entrain");
  CHECK(entrain.materials[2].grain.entrain == 128);
  CHECK(entrain.materials[5].grain.entrain == 128);  // gravel erodes as sand does, at its own roll cost
  CHECK(entrain.materials[3].grain.entrain == 0);   // a liquid has no slope to erode
  CHECK(rule_fingerprint(entrain) != rule_fingerprint(inertial));
  CHECK(entrain.materials[2].grain.flow_level == 0);
  const RuleSet flow = preset("inertial-24-flow");
  CHECK(flow.materials[2].grain.entrain == 128);
  CHECK(flow.materials[2].grain.flow_level == 1);
  CHECK(flow.materials[5].grain.flow_level == 1);  // gravel flows as slowly as sand
  CHECK(flow.materials[3].grain.flow_level == 0);  // a liquid keeps its speed
  CHECK(rule_fingerprint(flow) != rule_fingerprint(entrain));
  const RuleSet pressure = preset("inertial-24-pressure");
  CHECK(pressure.motion.pressure);
  CHECK_FALSE(flow.motion.pressure);
  CHECK(pressure.materials[2].grain.flow_level == flow.materials[2].grain.flow_level);  // sand as in the default
  CHECK(rule_fingerprint(pressure) != rule_fingerprint(flow));
  const RuleSet momentum = preset("inertial-24-momentum");
  CHECK(momentum.motion.pressure);
  CHECK(momentum.motion.momentum);
  CHECK_FALSE(pressure.motion.momentum);
  CHECK(rule_fingerprint(momentum) != rule_fingerprint(pressure));
  CHECK(rule_preset_names().size() == 11);
  for (const auto& name : rule_preset_names()) CHECK(preset(name).name == name);
}

TEST_CASE("rule set: WorldDef::rule_set wins over WorldDef::rules, and a changed table changes the world") {
  // State 6 is a static obstacle in the shipped table: a column of it stays in the air.
  auto shipped = std::make_shared<const RuleSet>(preset("paper"));
  CHECK(settled_on_floor(shipped, 6, 40) == 0);
  // Made granular (a game's own grain), it falls and piles on the floor, with no change to the library.
  RuleSet pebbles = preset("paper");
  pebbles.name = "paper-with-pebbles";
  pebbles.materials[6].name = "pebbles";
  pebbles.materials[6].behaviour = Behaviour::Granular;
  pebbles.materials[6].density = 3;
  CHECK(settled_on_floor(std::make_shared<const RuleSet>(pebbles), 6, 40) > 0);
  // The same under the motion model (its step reads the table's grain motion per material).
  RuleSet inertial = preset("inertial");
  inertial.name = "inertial-with-pebbles";
  inertial.materials[6] = inertial.materials[2];
  inertial.materials[6].name = "pebbles";
  CHECK(settled_on_floor(std::make_shared<const RuleSet>(inertial), 6, 40) > 0);
  CHECK(settled_on_floor(std::make_shared<const RuleSet>(preset("inertial")), 6, 40) == 0);
  // And WorldDef::rules is ignored when rule_set is set.
  WorldDef def;
  def.size = {8, 8, 8};
  def.backend = BackendKind::Cpu;
  def.rules = "no-such-preset";
  def.rule_set = shipped;
  CHECK(World(def).rules().name == "paper");
}

TEST_CASE("rule set: a table the step cannot run is refused, naming the field and value") {
  auto make = [](const RuleSet& r) {
    WorldDef def;
    def.size = {8, 8, 8};
    def.backend = BackendKind::Cpu;
    def.rule_set = std::make_shared<const RuleSet>(r);
    return World(def);
  };
  RuleSet r = preset("paper");
  r.materials[3].behaviour = Behaviour::Void;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[3].behaviour = void; only state 0 may be void"),
                       RuleError);
  r = preset("paper");
  r.materials[0].behaviour = Behaviour::Granular;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("state 0 must be void"), RuleError);
  r = preset("paper");
  for (int s = 1; s < kMaterialCount; ++s) {
    r.materials[std::size_t(s)].behaviour = Behaviour::Granular;
    r.materials[std::size_t(s)].density = 3;
  }
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("no static material"), RuleError);
  r = preset("paper");
  r.materials[4].density = 2;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[4].density = 2 for a gas material"), RuleError);
  r = preset("paper");
  r.materials[3].density = 0;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[3].density = 0 for a liquid material"), RuleError);
  r = preset("paper");
  r.materials[5].density = 65;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[5].density = 65; densities are -64..64"), RuleError);
  r = preset("paper");
  r.materials[3].spread = -1;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[3].spread = -1"), RuleError);
  r = preset("paper");
  r.materials[3].colour = 0x1000000;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[3].colour = 16777216"), RuleError);
  r = preset("inertial");
  r.materials[2].grain.roll_chance = 300;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[2].grain.roll_chance = 300"), RuleError);
  r = preset("inertial");
  r.materials[5].grain.entrain = -1;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[5].grain.entrain = -1"), RuleError);
  r.materials[5].grain.entrain = 0;
  r.materials[5].grain.flow_level = 16;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[5].grain.flow_level = 16; a motion level is 0..15"),
                       RuleError);
  r = preset("inertial");
  r.motion.substeps = 12;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::motion.substeps = 12"), RuleError);
  r = preset("paper");
  r.materials[4].name = "solid";
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[4].name = 'solid' is used twice"), RuleError);
  r = preset("paper");
  r.materials[6].behaviour = Behaviour(9);
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::materials[6].behaviour = 9 is not a Behaviour"), RuleError);
  r = preset("paper");
  r.transition = nullptr;
  CHECK_THROWS_WITH_AS(make(r), doctest::Contains("RuleSet::transition is null"), RuleError);
}
