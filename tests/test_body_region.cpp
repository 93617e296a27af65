/// @file test_body_region.cpp
/// The surroundings of a body's layers (for_each_cell_beside, bodies/body_region.hpp), which the
/// stamp keeps its pushes out of and sand_forces reads the buoyancy from, against the definition
/// taken a cell at a time: regions narrower and wider than a 64-cell word, every reach the code may
/// use, sets of every density, cells on the region's faces.

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "bodies/body_region.hpp"

namespace granular {
namespace {

/// The cells of `region` not in `in` within `reach` (in x and y, same layer) of a cell of `in` with
/// a side neighbour in its layer outside `in` or the region, as local indices.
std::set<std::uint32_t> beside_by_definition(const BodyRegion& region, const std::vector<std::uint8_t>& in, int reach) {
  auto held = [&](Int3 c) { return region.inside(c) && in[region.local(c)] != 0; };
  std::set<std::uint32_t> out;
  for (std::uint32_t i = 0; i < region.volume(); ++i) {
    const Int3 c = region.cell(i);
    if (!in[i]) continue;
    if (held({c.x + 1, c.y, c.z}) && held({c.x - 1, c.y, c.z}) && held({c.x, c.y + 1, c.z}) &&
        held({c.x, c.y - 1, c.z}))
      continue;
    for (int y = c.y - reach; y <= c.y + reach; ++y)
      for (int x = c.x - reach; x <= c.x + reach; ++x)
        if (region.inside({x, y, c.z}) && !held({x, y, c.z})) out.insert(region.local({x, y, c.z}));
  }
  return out;
}

}  // namespace

TEST_CASE("a layer's surroundings from bit rows are the cells within reach of its edge cells") {
  std::mt19937 rng(7);
  std::vector<std::uint64_t> rows;
  int sets = 0;
  for (const int width : {1, 5, 63, 64, 65, 130})
    for (const int reach : {0, 1, 2, 3})
      for (const double density : {0.05, 0.5, 0.95}) {
        const BodyRegion region(Box{{-3, 10, 4}, {-3 + width, 10 + 9, 4 + 4}});
        std::bernoulli_distribution pick(density);
        std::vector<std::uint8_t> in(region.volume(), 0);
        std::vector<Int3> cells;
        for (std::uint32_t i = 0; i < region.volume(); ++i)
          if (pick(rng)) {
            in[i] = 1;
            cells.push_back(region.cell(i));
          }
        std::shuffle(cells.begin(), cells.end(), rng);  // the helper takes the cells in any order
        std::multiset<std::uint32_t> got;
        bool layers_right = true;
        for_each_cell_beside(region, cells, reach, rows, [&](std::uint32_t i, int z) {
          got.insert(i);
          layers_right = layers_right && region.cell(i).z == region.box.min.z + z;
        });
        CHECK(layers_right);
        const std::set<std::uint32_t> want = beside_by_definition(region, in, reach);
        CAPTURE(width);
        CAPTURE(reach);
        CAPTURE(density);
        CHECK(got == std::multiset<std::uint32_t>(want.begin(), want.end()));  // each cell once
        sets += !want.empty();
      }
  CHECK(sets > 50);  // most sets have surroundings to compare
}

TEST_CASE("a set of no cells has no surroundings") {
  const BodyRegion region(Box{{0, 0, 0}, {8, 8, 8}});
  std::vector<std::uint64_t> rows;
  int calls = 0;
  for_each_cell_beside(region, std::vector<Int3>{}, 2, rows, [&](std::uint32_t, int) { ++calls; });
  CHECK(calls == 0);
}

}  // namespace granular
