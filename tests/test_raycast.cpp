#include <doctest/doctest.h>

#include <random>

#include "granular/errors.hpp"
#include "granular/raycast.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::random_grid;
using granular::test::test_def;

namespace {

Grid floor_grid() {
  Grid grid({8, 8, 8});
  grid.fill(Box{{0, 0, 0}, {8, 8, 2}}, Material::Solid);
  grid.set({5, 5, 2}, Material::Granular);
  return grid;
}

}  // namespace

TEST_CASE("raycast: a ray straight down stops on the top face of the floor") {
  const auto hit = raycast(floor_grid(), {2.5, 3.5, 20.0}, {0, 0, -1});
  REQUIRE(hit);
  CHECK(hit->cell == Int3{2, 3, 1});
  CHECK(hit->normal == Int3{0, 0, 1});
  CHECK(hit->in_front() == Int3{2, 3, 2});
  CHECK(hit->material == Material::Solid);
  CHECK(hit->distance == doctest::Approx(18.0));
  CHECK(hit->point.z == doctest::Approx(2.0));
}

TEST_CASE("raycast: a slanted ray finds the grain before the floor, entering through its side") {
  const auto hit = raycast(floor_grid(), {0.0, 5.5, 2.5}, {1, 0, 0});
  REQUIRE(hit);
  CHECK(hit->cell == Int3{5, 5, 2});
  CHECK(hit->normal == Int3{-1, 0, 0});
  CHECK(hit->material == Material::Granular);
  CHECK(hit->distance == doctest::Approx(5.0));
}

TEST_CASE("raycast: misses, short rays and rays starting inside a cell") {
  const Grid grid = floor_grid();
  CHECK_FALSE(raycast(grid, {2.5, 3.5, 20.0}, {0, 0, 1}));        // pointing away
  CHECK_FALSE(raycast(grid, {-5.0, -5.0, 20.0}, {-1, 0, -1}));    // never enters the grid
  CHECK_FALSE(raycast(grid, {2.5, 3.5, 20.0}, {0, 0, -1}, 10.0)); // stops before the floor
  const auto inside = raycast(grid, {2.5, 3.5, 0.5}, {0, 0, 1});
  REQUIRE(inside);
  CHECK(inside->cell == Int3{2, 3, 0});
  CHECK(inside->normal == Int3{0, 0, 0});
  CHECK(inside->distance == 0.0);
}

TEST_CASE("raycast: bad rays are errors") {
  const Grid grid = floor_grid();
  CHECK_THROWS_AS(raycast(grid, {0, 0, 0}, {0, 0, 0}), InvalidArgument);
  CHECK_THROWS_AS(raycast(grid, {0, 0, std::nan("")}, {0, 0, 1}), InvalidArgument);
  CHECK_THROWS_AS(raycast(grid, {0, 0, 0}, {0, 0, 1}, -1.0), InvalidArgument);
}

TEST_CASE("raycast: through a World (brick by brick) it agrees with the host grid on random rays") {
  const Int3 size{37, 29, 41};
  const Grid grid = random_grid(size, 7, 1, 2);
  World world(test_def(size), grid);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> position(-20.0, 60.0), inside(0.0, 29.0);
  int hits = 0;
  for (int i = 0; i < 300; ++i) {
    // From anywhere (inside or outside the grid) towards a random point of the grid.
    const Vec3 origin{position(rng), position(rng), position(rng)};
    const Vec3 dir{inside(rng) - origin.x, inside(rng) - origin.y, inside(rng) - origin.z};
    const auto from_grid = raycast(grid, origin, dir);
    const auto from_world = raycast(world, origin, dir);
    REQUIRE(from_grid.has_value() == from_world.has_value());
    if (!from_grid) continue;
    ++hits;
    CHECK(from_grid->cell == from_world->cell);
    CHECK(from_grid->normal == from_world->normal);
    CHECK(from_grid->distance == doctest::Approx(from_world->distance));
    // The hit is the first non-void cell: the cell just before it along the ray is void or outside.
    CHECK(grid.at(from_grid->cell) != Material::Void);
    const Int3 front = from_grid->in_front();
    if (from_grid->distance > 0 && grid.contains(front)) CHECK(grid.at(front) == Material::Void);
  }
  CHECK(hits > 200);
}
