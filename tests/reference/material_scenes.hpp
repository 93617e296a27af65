#pragma once
/// @file material_scenes.hpp
/// Scenes over every material of the presets (void, solid, sand, water, gas, gravel and the static
/// states 6 and 7) for the checks of the fast step against the plain loop, the golden hashes and
/// the GPU suite. Header-only: the GPU suite includes it without linking the plain loop. Cells are
/// drawn from a hash of (seed, cell), not from a standard distribution, so a scene is the same with
/// every compiler and standard library (a golden hash pins one).

#include <cstdint>

#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/material.hpp"

namespace granular::test {

/// A draw in 0..99 for cell (x, y, z) of a scene with seed `seed` (splitmix64 of both).
inline int scene_percent(std::uint64_t seed, int x, int y, int z) {
  std::uint64_t v = seed * 0x9E3779B97F4A7C15ull + (std::uint64_t(std::uint32_t(x)) | (std::uint64_t(std::uint32_t(y)) << 21) |
                                                    (std::uint64_t(std::uint32_t(z)) << 42));
  v = (v ^ (v >> 30)) * 0xBF58476D1CE4E5B9ull;
  v = (v ^ (v >> 27)) * 0x94D049BB133111EBull;
  return int((v ^ (v >> 31)) % 100u);
}

/// A random scene holding every one of the 8 states: below half height a rough ground (sand 22%,
/// gravel 8%, solid 10%, water 20%, gas 8%, states 6 and 7 2% each, void the rest), so water sits on
/// and between grains with gas under it; above, sand, gravel and water falling through void (10%, 4%,
/// 8%) and some gas (3%). Every faller starts at rest (no motion bits).
inline Grid all_materials_scene(Int3 size, std::uint64_t seed) {
  Grid g(size);
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const int p = scene_percent(seed, x, y, z);
        Material m = Material::Void;
        if (z < size.z / 2) {
          if (p < 22) m = Material::Granular;
          else if (p < 30) m = Material::Gravel;
          else if (p < 40) m = Material::Solid;
          else if (p < 60) m = Material::Liquid;
          else if (p < 68) m = Material::Gas;
          else if (p < 70) m = Material::State6;
          else if (p < 72) m = Material::State7;
        } else {
          if (p < 10) m = Material::Granular;
          else if (p < 14) m = Material::Gravel;
          else if (p < 22) m = Material::Liquid;
          else if (p < 25) m = Material::Gas;
        }
        g.set({x, y, z}, m);
      }
  return g;
}

/// The golden scene of every material at size parameter n (an n x n x n grid): a pool of water on
/// the floor over the left 5/8 of the grid, 5/16 n deep, with gas pockets on its floor; a solid shelf
/// over the right part at 7/16 n with gas under it (which spreads under the shelf and around its edge);
/// a block of sand and a block of gravel above the pool that fall into it and sink; a slab of water
/// on the shelf that runs off its edge; a few cells of the static states 6 and 7 on the floor; and 2%
/// of each of sand, gravel, water and gas scattered in the air.
inline Grid all_materials_pool(int n) {
  Grid g({n, n, n});
  auto in = [](int v, int lo, int hi) { return v >= lo && v < hi; };
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        Material m = Material::Void;
        const int p = scene_percent(0x601DE4, x, y, z);
        if (p < 2) m = Material::Granular;
        else if (p < 4) m = Material::Gravel;
        else if (p < 6) m = Material::Liquid;
        else if (p < 8) m = Material::Gas;
        if (in(x, 0, 5 * n / 8) && in(z, 0, 5 * n / 16)) {
          m = Material::Liquid;
          if (z < 3 && (p % 7) == 0) m = Material::Gas;  // pockets on the pool's floor
        }
        if (in(x, 5 * n / 8, n) && in(z, 5 * n / 16, 7 * n / 16)) m = Material::Gas;  // under the shelf
        if (in(x, 9 * n / 16, n) && in(y, n / 8, 7 * n / 8) && z == 7 * n / 16) m = Material::Solid;  // the shelf
        if (in(x, 10 * n / 16, 15 * n / 16) && in(y, n / 4, 3 * n / 4) && in(z, 7 * n / 16 + 1, 7 * n / 16 + 3))
          m = Material::Liquid;  // water on the shelf
        if (in(x, n / 8, 5 * n / 16) && in(y, n / 4, n / 2) && in(z, 5 * n / 8, 13 * n / 16)) m = Material::Granular;
        if (in(x, 5 * n / 16, n / 2) && in(y, n / 2, 3 * n / 4) && in(z, 11 * n / 16, 7 * n / 8)) m = Material::Gravel;
        if (z == 0 && (p == 50 || p == 51)) m = p == 50 ? Material::State6 : Material::State7;
        g.set({x, y, z}, m);
      }
  return g;
}

}  // namespace granular::test
