/// @file embed_minimal.cpp
/// The smallest game loop that embeds granular: make a world, shape it, tick it, use the tools.
/// Exits non-zero if sand was created or destroyed, so the test suite runs it as a check.

#include <granular/granular.hpp>

#include <cstdio>

int main() {
  granular::WorldDef def;                 // defaults: auto backend, inertial-24-flow rules, seed 0
  def.size = {64, 64, 64};
  granular::World world(def);
  world.paint(granular::Box{{0, 0, 0}, {64, 64, 2}}, granular::Material::Solid);         // a floor
  world.paint(granular::Box{{16, 16, 40}, {48, 48, 60}}, granular::Material::Granular);  // a block of sand

  const auto before = world.count();
  std::uint64_t dug = 0, poured = 0;
  for (int frame = 0; frame < 240; ++frame) {  // the game's loop: one fixed tick per frame
    world.step(1);
    if (frame == 120) dug = std::uint64_t(world.dig({{32, 32, 8}, 6.0}).cells_changed);
    if (frame >= 150 && frame < 170)
      poured += std::uint64_t(world.pour({32, 32, 50}, 3.0, granular::Material::Granular, 20).cells_changed);
  }

  const auto after = world.count();
  const auto grains = [](const granular::MaterialCounts& c) { return c[granular::to_cell(granular::Material::Granular)]; };
  std::printf("ticks %llu, grains %llu -> %llu (dug %llu, poured %llu), hash %016llx\n",
              static_cast<unsigned long long>(world.tick()), static_cast<unsigned long long>(grains(before)),
              static_cast<unsigned long long>(grains(after)), static_cast<unsigned long long>(dug),
              static_cast<unsigned long long>(poured), static_cast<unsigned long long>(world.hash()));
  return grains(after) == grains(before) - dug + poured ? 0 : 1;
}
