#include <doctest/doctest.h>

#include "granular/scene.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;

namespace {

/// Steps until the grid is unchanged over a whole 8-offset cycle; returns the ticks taken.
std::uint64_t run_until_settled(World& world, std::uint64_t max_ticks) {
  std::uint64_t previous = world.hash();
  while (world.tick() < max_ticks) {
    world.step(8);
    const std::uint64_t h = world.hash();
    if (h == previous) return world.tick();
    previous = h;
  }
  return world.tick();
}

}  // namespace

TEST_CASE("bowl: the paper's benchmark ends with the bowl filled and buried (Figure 4.2b)") {
  for (int n : {35, 48}) {
    CAPTURE(n);
    const SceneInstance scene = instantiate(load_scene(find_scene("bowl")), n);
    const Grid& start = scene.grid;
    World world(test::test_def(start.size()), start);
    const std::uint64_t ticks = run_until_settled(world, 20000);
    CHECK(ticks < 20000);  // it comes to rest
    const Grid end = world.read_grid();
    CHECK(end.count() == start.count());

    int rim = -1;
    std::int64_t bowl_columns = 0, buried_columns = 0, cavity = 0, cavity_filled = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (int z = n - 1; z >= 0; --z)
          if (start.at({x, y, z}) == Material::Solid) {
            rim = std::max(rim, z);
            break;
          }
    REQUIRE(rim > 0);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        int top_solid = -1, bottom_solid = -1;
        for (int z = 0; z < n; ++z)
          if (start.at({x, y, z}) == Material::Solid) {
            if (bottom_solid < 0) bottom_solid = z;
            top_solid = z;
          }
        if (top_solid < 0) continue;
        ++bowl_columns;
        // Buried: sand lies on the bowl's top cell in every column the bowl occupies.
        buried_columns += top_solid + 1 < n && end.at({x, y, top_solid + 1}) == Material::Granular;
        // Filled: every cavity cell (void above the bowl's wall, up to the rim) holds sand.
        for (int z = top_solid + 1; z <= rim; ++z) {
          ++cavity;
          cavity_filled += end.at({x, y, z}) == Material::Granular;
        }
      }
    CHECK(bowl_columns > 0);
    CHECK(buried_columns == bowl_columns);
    CHECK(cavity > 0);
    CHECK(cavity_filled == cavity);
    // The sand also flowed underneath the floating bowl: the floor below its centre is covered.
    CHECK(end.at({n / 2, n / 2, 0}) == Material::Granular);
  }
}
