/// @file test_body_throw.cpp
/// Where the sandbox's throw starts and how fast it flies (bodies/body_throw.hpp), and what the body
/// watch says about a body that falls, lands and comes to rest (bodies/body_watch.hpp). Pure logic:
/// no window, no Bullet.

#include <doctest/doctest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "bodies/body_throw.hpp"
#include "bodies/body_watch.hpp"
#include "granular/rule_presets.hpp"

using namespace viewer;

namespace {

constexpr double kCell = 0.005;     // m
constexpr double kTick = 0.031928;  // s, about the default rules' tick

granular::BodyDef aimed(const ThrowChoice& choice, granular::Vec3 origin, granular::Vec3 direction,
                        granular::Int3 size = {128, 128, 128}) {
  const auto def = aim_throw(choice, origin, direction, size, 2.0, kCell, kTick);
  REQUIRE(def);
  return *def;
}

}  // namespace

TEST_CASE("throw: from a camera outside the grid, the body starts where its bounding sphere is a cell inside") {
  ThrowChoice ball;  // radius 4: it starts 5 cells inside each face it crosses
  const granular::BodyDef def = aimed(ball, {64, 64, 300}, {0, 0, -1});
  CHECK(def.shape == granular::BodyShape::Sphere);
  CHECK(def.radius == 4);
  CHECK(def.density == 800);
  CHECK(def.pose.position.x == doctest::Approx(64));
  CHECK(def.pose.position.y == doctest::Approx(64));
  CHECK(def.pose.position.z == doctest::Approx(128 - 5));
  // 2 m/s along the ray: 2 * 0.031928 / 0.005 = 12.77 cells a tick, straight down.
  CHECK(def.pose.velocity.z == doctest::Approx(-2.0 * kTick / kCell));
  CHECK(def.pose.velocity.x == doctest::Approx(0));

  ThrowChoice box{granular::BodyShape::Box, 4, 2000};  // a cube turns: its corners reach 4 sqrt(3) cells
  const granular::BodyDef cube = aimed(box, {-100, 64, 64}, {1, 0, 0});
  CHECK(cube.shape == granular::BodyShape::Box);
  CHECK(cube.half_extents.x == 4);
  CHECK(cube.pose.position.x == doctest::Approx(4 * std::sqrt(3.0) + 1));
}

TEST_CASE("throw: from a camera inside the grid, the body starts just in front of it, along a slanted ray") {
  ThrowChoice ball;
  const double inv = 1 / std::sqrt(2.0);
  const granular::BodyDef def = aimed(ball, {64, 64, 64}, {inv, 0, -inv});
  CHECK(def.pose.position.x == doctest::Approx(64 + 5 * inv));  // radius + 1 cell in front of the eye
  CHECK(def.pose.position.z == doctest::Approx(64 - 5 * inv));
  CHECK(def.pose.velocity.x == doctest::Approx(-def.pose.velocity.z));
  const double speed = std::hypot(def.pose.velocity.x, def.pose.velocity.z) * kCell / kTick;
  CHECK(speed == doctest::Approx(2.0));
}

TEST_CASE("throw: a ray that misses the grid, points away from it, or a grid too small for the body gives none") {
  ThrowChoice ball;
  const granular::Int3 n{128, 128, 128};
  CHECK_FALSE(aim_throw(ball, {64, 64, 300}, {0, 0, 1}, n, 2.0, kCell, kTick));      // looking up, above the grid
  CHECK_FALSE(aim_throw(ball, {300, 64, 64}, {0, 1, 0}, n, 2.0, kCell, kTick));      // beside it, along it
  CHECK_FALSE(aim_throw(ball, {64, 64, 125}, {0, 0, 1}, n, 2.0, kCell, kTick));      // inside, too near the top
  CHECK_FALSE(aim_throw(ball, {4, 4, 4}, {1, 0, 0}, {9, 9, 9}, 2.0, kCell, kTick));  // 9 cells: no room for 10
  CHECK(aim_throw(ball, {5, 5, 5}, {1, 0, 0}, {10, 10, 10}, 2.0, kCell, kTick).has_value() == false);
  CHECK(aim_throw(ball, {5, 5, 100}, {0, 0, -1}, {10, 10, 10}, 2.0, kCell, kTick).has_value());  // exactly room
}

TEST_CASE("throw: bad input is an error naming it, never a clamp") {
  const granular::Int3 n{64, 64, 64};
  ThrowChoice small{granular::BodyShape::Sphere, 2, 800};
  CHECK_THROWS_WITH_AS(aim_throw(small, {32, 32, 200}, {0, 0, -1}, n, 2.0, kCell, kTick),
                       doctest::Contains("half size"), std::invalid_argument);
  ThrowChoice dense{granular::BodyShape::Box, 4, 20000};
  CHECK_THROWS_WITH_AS(aim_throw(dense, {32, 32, 200}, {0, 0, -1}, n, 2.0, kCell, kTick), doctest::Contains("density"),
                       std::invalid_argument);
  ThrowChoice capsule{granular::BodyShape::Capsule, 4, 800};
  CHECK_THROWS_WITH_AS(aim_throw(capsule, {32, 32, 200}, {0, 0, -1}, n, 2.0, kCell, kTick),
                       doctest::Contains("not a box or a ball"), std::invalid_argument);
  ThrowChoice ball;
  CHECK_THROWS_AS(aim_throw(ball, {32, 32, 200}, {0, 0, 0}, n, 2.0, kCell, kTick), std::invalid_argument);
  CHECK_THROWS_AS(aim_throw(ball, {32, 32, 200}, {0, 0, NAN}, n, 2.0, kCell, kTick), std::invalid_argument);
  CHECK_THROWS_AS(aim_throw(ball, {32, INFINITY, 200}, {0, 0, -1}, n, 2.0, kCell, kTick), std::invalid_argument);
  CHECK_THROWS_AS(aim_throw(ball, {32, 32, 200}, {0, 0, -1}, n, 0.0, kCell, kTick), std::invalid_argument);
  CHECK_THROWS_AS(aim_throw(ball, {32, 32, 200}, {0, 0, -1}, n, 2.0, -kCell, kTick), std::invalid_argument);
  CHECK_THROWS_AS(throw_speed({0, 64, 64}, kCell), std::invalid_argument);
  CHECK_THROWS_AS(throw_speed({64, 64, 64}, 0.0), std::invalid_argument);
}

TEST_CASE("throw: the speed crosses the grid in one free fall from its top; the size suits the grid") {
  // N = 128, 5 mm cells: 0.64 m in sqrt(2 * 0.64 / 9.81) = 0.361 s.
  CHECK(throw_speed({128, 128, 128}, kCell) == doctest::Approx(0.64 / std::sqrt(2 * 0.64 / 9.81)));
  CHECK(throw_speed({128, 64, 128}, kCell) == doctest::Approx(0.32 / std::sqrt(2 * 0.64 / 9.81)));
  CHECK(default_half_size({128, 128, 128}) == 4);
  CHECK(default_half_size({48, 48, 48}) == 3);
  CHECK(default_half_size({512, 512, 256}) == 6);
  CHECK(density_effect(300) == "floats in water and sand");
  CHECK(density_effect(1200) == "sinks in water, floats in sand");
  CHECK(density_effect(7800) == "sinks in water and sand");
}

TEST_CASE("body watch: a falling body lands when it first touches sand, beside its free fall's time, then rests") {
  const granular::RuleSet rules = granular::preset("inertial-24-flow");
  BodyWatch watch(rules.materials, kTick, kCell);
  const double g = 9.81 * kTick * kTick / kCell;  // cells per tick^2
  watch.follow(1, 100, {64, 64, 100}, {1, 0, 0});
  granular::BodySand air;  // nothing around it or under it: void
  air.cells = 268;
  air.below[0] = 40;
  granular::BodySand sand = air;
  sand.below = {};
  sand.below[2] = 40;  // granular under it
  sand.submerged[2] = 134;
  std::vector<std::string> lines;
  granular::Vec3 at{64, 64, 100};
  double vz = 0;
  std::uint64_t tick = 100;
  int landed_at = -1;
  for (; tick < 200; ++tick) {
    const bool touching = at.z <= 40;
    const BodyReading reading{1, at, at.z - 4, touching ? &sand : &air};
    for (const std::string& line : watch.observe(tick, {reading})) {
      lines.push_back(line);
      if (line.find("landed") != std::string::npos) landed_at = int(tick);
    }
    if (!touching) {  // falls as Bullet would, then stops in the sand
      vz -= g;
      at.z += vz;
      at.x += 1;
    }
  }
  REQUIRE(lines.size() == 2);
  CHECK(lines[0].rfind("body 1: landed in granular at tick ", 0) == 0);
  const double expected = BodyWatch::fall_ticks(100, 0, 40, g);
  CHECK(expected == doctest::Approx(std::sqrt(2 * 60 / g)));
  CHECK(std::abs((landed_at - 100) - expected) <= 1.0);
  CHECK(lines[1].rfind("body 1: at rest at tick " + std::to_string(landed_at + kRestTicks - 1), 0) == 0);
  CHECK(lines[1].find("50% submerged, on or in granular") != std::string::npos);
}

TEST_CASE("body watch: a body brought back lying in the sand gets no landing line; gone bodies are dropped") {
  const granular::RuleSet rules = granular::preset("inertial-24-flow");
  BodyWatch watch(rules.materials, kTick, kCell);
  watch.follow(4, 10, {20, 20, 20}, {}, false);
  watch.follow(5, 10, {40, 40, 40}, {});
  granular::BodySand sand;
  sand.cells = 100;
  sand.submerged[2] = 30;
  std::vector<std::string> lines;
  for (std::uint64_t tick = 10; tick < 10 + kRestTicks; ++tick)
    for (const std::string& line : watch.observe(tick, {{4, {20, 20, 20}, 16, &sand}})) lines.push_back(line);
  REQUIRE(lines.size() == 1);
  CHECK(lines[0].rfind("body 4: at rest", 0) == 0);
  CHECK(watch.size() == 2);
  watch.keep_only({5});
  CHECK(watch.size() == 1);
  CHECK_THROWS_AS(BodyWatch(rules.materials, 0.0, kCell), std::invalid_argument);
}
