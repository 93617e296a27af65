/// @file game_material.cpp
/// A game's own material with no change to the library: an oil (a liquid lighter than water) added
/// as a row of a copied rule set, poured onto water in a tank. Exits non-zero unless every material
/// is conserved and the oil ends floating on the water, so the test suite runs it as a check.

#include <granular/granular.hpp>

#include <cstdio>
#include <memory>

int main() {
  granular::RuleSet rules = granular::preset("inertial-24");
  rules.name = "inertial-24-with-oil";
  granular::MaterialDef& oil = rules.materials[6];  // state 6 is static in the presets: free for a game
  oil = rules.materials[granular::to_cell(granular::Material::Liquid)];  // moves as water does...
  oil.name = "oil";
  oil.density = 1;        // ...but floats on water (2); void is 0
  oil.spread = 128;       // walks sideways half as often as water
  oil.colour = 0x3A2A10;  // how a viewer draws it

  granular::WorldDef def;
  def.size = {32, 32, 32};
  def.rule_set = std::make_shared<const granular::RuleSet>(rules);
  granular::World world(def);
  const auto oil_state = granular::Material(6);
  world.paint(granular::Box{{0, 0, 0}, {32, 32, 1}}, granular::Material::Solid);           // floor
  world.paint(granular::Box{{0, 0, 1}, {32, 32, 8}}, granular::Material::Liquid);          // water
  const auto before_pour = world.count();
  std::uint64_t poured = 0;
  for (int frame = 0; frame < 400; ++frame) {  // the game's loop: one fixed tick per frame
    if (frame < 100) poured += std::uint64_t(world.pour({16, 16, 28}, 3.0, oil_state, 12).cells_changed);
    world.step(1);
  }

  // The oil should lie on the water: its lowest cell no lower than the water's top layer.
  const auto cells = world.read_region(granular::Box{{0, 0, 0}, {32, 32, 32}});
  int water_top = -1, oil_bottom = 32;
  for (int z = 0; z < 32; ++z)
    for (int i = 0; i < 32 * 32; ++i) {
      const auto c = cells[std::size_t(z) * 32 * 32 + std::size_t(i)];
      if (c == granular::to_cell(granular::Material::Liquid)) water_top = z;
      if (c == granular::to_cell(oil_state) && z < oil_bottom) oil_bottom = z;
    }
  const auto after = world.count();
  const bool conserved = after[6] == poured &&
                         after[granular::to_cell(granular::Material::Liquid)] ==
                             before_pour[granular::to_cell(granular::Material::Liquid)];
  std::printf("%s: %llu oil cells poured; water top layer z %d, oil bottom z %d; %s\n", rules.materials[6].name.c_str(),
              static_cast<unsigned long long>(poured), water_top, oil_bottom, conserved ? "conserved" : "NOT conserved");
  return conserved && poured > 0 && oil_bottom >= water_top ? 0 : 1;
}
