#pragma once
/// @file tool_session.hpp
/// A small world in motion with every kind of cell, and a player's tools between ticks: what the
/// snapshot and undo tests continue, stop, save and rewind.

#include <doctest/doctest.h>

#include <cstdint>

#include "granular/grid.hpp"
#include "granular/world.hpp"

namespace granular::test {

/// A `size` grid (at least 24 cells on each axis): a solid floor and wall, a falling slab of sand,
/// a block of water beside it and a pocket of gas under the sand.
inline Grid fluid_scene(Int3 size) {
  Grid g(size);
  g.fill(Box{{0, 0, 0}, {size.x, size.y, 2}}, Material::Solid);
  g.fill(Box{{size.x / 2, 0, 2}, {size.x / 2 + 1, size.y / 2, size.z / 3}}, Material::Solid);
  g.fill(Box{{2, 2, size.z / 2}, {size.x / 2, size.y - 2, size.z - 4}}, Material::Granular);
  g.fill(Box{{size.x / 2 + 2, 2, 2}, {size.x - 2, size.y - 2, size.z / 3}}, Material::Liquid);
  g.fill(Box{{4, 4, 2}, {size.x / 2 - 2, size.y / 2, 6}}, Material::Gas);
  return g;
}

/// The tools a player applies before tick `t`: pours of sand and water, digs and shakes at places
/// and times that vary with t (pour salts its choice with World::tool_calls()).
inline void apply_tools(World& world, std::uint64_t t) {
  const Int3 s = world.size();
  const double x = 4 + double(t * 7 % std::uint64_t(s.x - 8)), y = 4 + double(t * 5 % std::uint64_t(s.y - 8));
  if (t % 3 == 0) world.pour({x, y, s.z - 6.0}, 3.0, Material::Granular, 20);
  if (t % 4 == 1) world.pour({double(s.x) - x, y, s.z - 8.0}, 3.0, Material::Liquid, 15);
  if (t % 5 == 2) world.dig(Sphere{{x, double(s.y) - y, s.z / 2.0}, 4.0});
  if (t % 7 == 3 && world.rules().motion.enabled()) world.shake(Sphere{{x, y, s.z / 3.0}, 5.0}, 3);
}

/// `ticks` ticks of the session: the tools of each tick, then the tick.
inline void play(World& world, int ticks) {
  for (int i = 0; i < ticks; ++i) {
    apply_tools(world, world.tick());
    world.step(1);
  }
}

/// Plays `a` and `b` alike for `ticks` ticks, requiring the same tick and hash after every one.
inline void play_alike(World& a, World& b, int ticks) {
  for (int i = 0; i < ticks; ++i) {
    play(a, 1);
    play(b, 1);
    REQUIRE(a.tick() == b.tick());
    REQUIRE(a.hash() == b.hash());
  }
}

}  // namespace granular::test
