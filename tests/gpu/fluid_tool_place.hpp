#pragma once
/// @file fluid_tool_place.hpp
/// Where the GPU suite's fluid rounds pour and paint water and gas between ticks.

#include <cstdint>
#include <random>

#include "granular/geometry.hpp"

namespace granular::test {

/// A random tool call's place: a sphere (centre, radius) and an amount for pour, and a box at the
/// sphere's centre for paint; either may reach outside the grid or miss it.
struct FluidToolPlace {
  Vec3 centre;          ///< sphere centre, over the upper two thirds of the grid
  double radius;        ///< 1.5 .. 5.5 cells
  std::int64_t amount;  ///< cells to pour, 20 .. 219
  Box box;              ///< a box of 2..9 x 2..9 x 1..4 cells near the centre
};

/// The next place drawn from `rng` for a grid of `size`.
inline FluidToolPlace random_fluid_tool_place(std::mt19937_64& rng, Int3 size) {
  std::uniform_real_distribution<double> ux(-2.0, size.x + 2.0), uy(-2.0, size.y + 2.0), uz(size.z / 3.0, size.z + 2.0);
  FluidToolPlace p{};
  p.centre = Vec3{ux(rng), uy(rng), uz(rng)};
  p.radius = 1.5 + double(rng() % 5);
  p.amount = 20 + std::int64_t(rng() % 200);
  const Int3 lo{int(p.centre.x) - 3, int(p.centre.y) - 3, int(p.centre.z) - 2};
  p.box = Box{lo, {lo.x + 2 + int(rng() % 8), lo.y + 2 + int(rng() % 8), lo.z + 1 + int(rng() % 4)}};
  return p;
}

}  // namespace granular::test
