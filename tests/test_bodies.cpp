/// @file test_bodies.cpp
/// Rigid bodies in the sand (World::add_body, docs/design/bodies.md): a body is written as cells of
/// the body material and leaves void behind; bodies moving through sand and water conserve every
/// material exactly and stay deterministic (thread counts, sparse = dense); a box of half the bulk
/// density of sand or water floats half submerged and one of twice sinks to the floor, moved by a
/// game's own few lines of physics; a ball rolled over a bed leaves a groove and stops sooner in
/// deeper sand; water closes behind a crate pushed through a pool; a capsule walked through a dune
/// leaves it whole; bodies half out of the grid, leaving it, jumping far and overlapping keep every
/// cell; bad input is refused by name; World::profile times the bodies' phases.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "body_scene.hpp"
#include "granular/body.hpp"
#include "granular/errors.hpp"
#include "granular/step_profile.hpp"
#include "granular/time_scale.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::check_has;
using granular::test::error_of;
using granular::test::test_def;

namespace {

constexpr const char* kRules = "inertial-24-flow";
constexpr std::uint8_t kBody = to_cell(Material::State7);

/// The cells of `w` holding `m`.
std::uint64_t cells_of(const World& w, Material m) { return w.count()[to_cell(m)]; }

/// A game's own coupling, without a physics engine: each tick the sand's force and gravity
/// accelerate the body (its centre only), the grid's floor stops its fall `half_height` cells above
/// it, and the new pose is handed back to the world.
struct OwnPhysics {
  World& world;
  BodyId id;
  double half_height;
  BodyPose pose;
  Vec3 velocity;  // m/s
  double tick_s = tick_seconds(world.rules(), world.def().cell_metres);
  double per_cell = tick_s / world.def().cell_metres;  // m/s to cells per tick

  OwnPhysics(World& w, BodyId body, double half) : world(w), id(body), half_height(half), pose(w.body_pose(body)) {}

  void tick() {
    world.step(1);
    const BodySand& sand = world.body_sand(id);
    velocity.x += sand.force.x / sand.mass * tick_s;
    velocity.y += sand.force.y / sand.mass * tick_s;
    velocity.z += (sand.force.z / sand.mass - kStandardGravity) * tick_s;
    if (velocity.z < 0 && pose.position.z + velocity.z * per_cell < half_height) {
      velocity.z = 0;
      pose.position.z = half_height;
    }
    pose.velocity = {velocity.x * per_cell, velocity.y * per_cell, velocity.z * per_cell};
    pose.position = {pose.position.x + pose.velocity.x, pose.position.y + pose.velocity.y,
                     pose.position.z + pose.velocity.z};
    world.set_body_pose(id, pose);
  }
};

/// The mean height of the top of `medium` in the columns 1 to 3 cells around the footprint
/// [x0, x1) x [y0, y1) (the local surface a floating body sits in).
double surface_around(const World& w, Material medium, int x0, int x1, int y0, int y1) {
  const Int3 n = w.size();
  double sum = 0;
  int columns = 0;
  for (int y = y0 - 3; y < y1 + 3; ++y)
    for (int x = x0 - 3; x < x1 + 3; ++x) {
      if (x >= x0 - 1 && x < x1 + 1 && y >= y0 - 1 && y < y1 + 1) continue;
      const std::vector<std::uint8_t> column = w.read_region(Box{{x, y, 0}, {x + 1, y + 1, n.z}});
      int top = 0;
      for (int z = 0; z < n.z; ++z)
        if (column[std::size_t(z)] == to_cell(medium)) top = z + 1;
      sum += top;
      ++columns;
    }
  return sum / columns;
}

/// A box of half size 5 and `density` dropped from 6 cells over a settled bed of `medium` 24 cells
/// deep, moved by OwnPhysics for `ticks` ticks. Returns the share of its height below the local
/// surface, averaged over the last 100 ticks, and sets `lowest` / `highest` to its centre's range
/// over them, `awake` to the bricks the last tick stepped and `*hash` (when given) to a hash of the
/// cells and the centre; `sparse` as WorldDef::sparse.
double float_box(Material medium, double density, int ticks, double& lowest, double& highest, std::uint64_t& awake,
                 std::uint64_t* hash = nullptr, bool sparse = true) {
  World w(test::with_sparse(test_def({48, 48, 56}, kRules), sparse));
  w.paint(Box{{0, 0, 0}, {48, 48, 24}}, medium);
  w.step(medium == Material::Liquid ? 5 : 40);
  const MaterialCounts before = w.count();
  BodyDef def;
  def.density = density;
  def.half_extents = {5, 5, 5};
  def.pose.position = {24, 24, 35};
  OwnPhysics body(w, w.add_body(def), 5);
  double below = 0;
  lowest = 1e9;
  highest = -1e9;
  for (int t = 0; t < ticks; ++t) {
    body.tick();
    if (t >= ticks - 100) {
      const double z = body.pose.position.z;
      lowest = std::min(lowest, z);
      highest = std::max(highest, z);
      const double surface = surface_around(w, medium, 19, 29, 19, 29);
      below += std::clamp((surface - (z - 5)) / 10, 0.0, 1.0) / 100;
    }
  }
  awake = w.activity().active_bricks;
  if (hash) *hash = w.hash() ^ std::uint64_t(std::llround(body.pose.position.z * 1e6));
  const MaterialCounts after = w.count();
  for (int m = 0; m < kMaterialCount; ++m)
    if (m != 0 && m != kBody) CHECK(after[std::size_t(m)] == before[std::size_t(m)]);
  return below;
}

}  // namespace

TEST_CASE("a body is written as cells of the body material, and the cells it leaves become void") {
  World w(test_def({32, 32, 32}, kRules));
  BodyDef def;
  def.half_extents = {3, 3, 3};
  def.pose.position = {16, 16, 16};
  const BodyId id = w.add_body(def);
  CHECK(w.body_sand(id).cells == 0);  // written from the next tick on
  w.step(1);
  CHECK(cells_of(w, Material::State7) == 216);  // centres 13.5 .. 18.5 on each axis
  CHECK(w.body_sand(id).cells == 216);
  CHECK(w.read_region(Box{{13, 13, 13}, {14, 14, 14}})[0] == kBody);
  BodyPose pose = w.body_pose(id);
  pose.position.x += 1;
  w.set_body_pose(id, pose);
  w.step(1);
  CHECK(cells_of(w, Material::State7) == 216);
  CHECK(w.read_region(Box{{13, 13, 13}, {14, 14, 14}})[0] == 0);
  CHECK(w.read_region(Box{{19, 13, 13}, {20, 14, 14}})[0] == kBody);
  // A velocity moves it on by itself, a tick at a time.
  pose = w.body_pose(id);
  pose.velocity = {0, 0, -2};
  w.set_body_pose(id, pose);
  w.step(3);
  CHECK(w.body_pose(id).position.z == doctest::Approx(10));
  CHECK(w.read_region(Box{{15, 15, 9}, {16, 16, 10}})[0] == kBody);  // written at z = 12: cells 9 .. 14
  w.remove_body(id);
  CHECK(cells_of(w, Material::State7) == 0);
  CHECK(w.body_ids().empty());
}

TEST_CASE("World::profile gives the phases of the last step call, the bodies' among them") {
  World w(test_def({48, 48, 40}, kRules));
  w.paint(Box{{0, 0, 0}, {48, 48, 12}}, Material::Granular);
  w.step(3);
  StepProfile p = w.profile();
  CHECK(p.ticks == 3);
  CHECK(p.step > 0);
  CHECK(p.bodies == 0);
  CHECK(p.total >= p.step);
  granular::test::WanderingBodies bodies(w);
  for (int call = 0; call < 2; ++call) {
    w.step(2 - call);
    p = w.profile();
    CHECK(p.ticks == std::uint64_t(2 - call));  // the last call's, not a sum over calls
    CHECK(p.bodies > 0);
    CHECK(p.bodies_shapes > 0);
    CHECK(p.bodies_read > 0);
    CHECK(p.bodies_stamp > 0);
    CHECK(p.bodies_write >= 0);
    CHECK(p.bodies_forces > 0);
    // On the CPU the forces are found before the step, as part of the bodies' work.
    CHECK(p.bodies_shapes + p.bodies_read + p.bodies_stamp + p.bodies_write + p.bodies_forces <= p.bodies * (1 + 1e-9));
    CHECK(p.total >= (p.step + p.bodies) * (1 - 1e-9));
  }
}

TEST_CASE("bodies moving through sand and water conserve every material, and are deterministic") {
  // Ten bodies of every shape wander through a bed of sand under water with gravel in it for 2,000
  // ticks (64 s); the same run on one and two threads, and densely stepped, ends in the same cells.
  auto run = [](int threads, bool sparse, int ticks) {
    World w(test::with_sparse(test_def({48, 48, 40}, kRules, threads, 7), sparse));
    test::WanderingBodies bodies(w);
    const std::vector<BodyId>& ids = bodies.ids;
    const MaterialCounts before = w.count();
    for (int t = 0; t < ticks; ++t) {
      bodies.tick();
      if (t % 100 == 99) {
        const MaterialCounts now = w.count();
        std::int64_t held = 0;
        for (const BodyId id : ids) held += w.body_sand(id).cells;
        REQUIRE(std::int64_t(now[kBody]) == held);
        for (int m = 1; m < kMaterialCount; ++m)
          if (m != kBody) REQUIRE(now[std::size_t(m)] == before[std::size_t(m)]);
      }
    }
    std::int64_t pushed = 0;
    for (const BodyId id : ids)
      for (const auto d : w.body_sand(id).displaced) pushed += std::int64_t(d);
    return std::pair{w.hash(), pushed};
  };
  const auto [two, pushed] = run(2, true, 2000);
  CHECK(pushed >= 0);
  const auto [one, pushed_one] = run(1, true, 200);
  const auto [dense, pushed_dense] = run(2, false, 200);
  const auto [two_short, pushed_short] = run(2, true, 200);
  CHECK(one == two_short);
  CHECK(dense == two_short);
  CHECK(pushed_one == pushed_short);
  CHECK(pushed_dense == pushed_short);
  (void)two;
}

TEST_CASE("a box of half the bulk density floats half submerged, one of twice sinks to the floor") {
  double lowest = 0, highest = 0;
  std::uint64_t awake = 0;
  SUBCASE("in sand") {
    const double below = float_box(Material::Granular, 800, 300, lowest, highest, awake);
    std::printf("box of 800 kg/m^3 in sand: %.3f of its height below the surface around it, centre %.2f .. %.2f\n",
                below, lowest, highest);
    CHECK(below == doctest::Approx(0.5).epsilon(0.2));
    CHECK(highest - lowest < 1.0);
    CHECK(awake == 0);  // a body at rest lets the sand around it sleep
    // At rest, a body whose region nothing changed is not written again (stamp_bodies); dense
    // stepping, where every brick counts as changed, writes it every tick: the same cells and pose.
    std::uint64_t sparse_hash = 0, dense_hash = 0;
    float_box(Material::Granular, 800, 150, lowest, highest, awake, &sparse_hash, true);
    float_box(Material::Granular, 800, 150, lowest, highest, awake, &dense_hash, false);
    CHECK(sparse_hash == dense_hash);
    float_box(Material::Granular, 3200, 100, lowest, highest, awake);
    CHECK(lowest == doctest::Approx(5));  // its bottom on the floor
  }
  SUBCASE("in water") {
    const double below = float_box(Material::Liquid, 500, 300, lowest, highest, awake);
    std::printf("box of 500 kg/m^3 in water: %.3f of its height below the surface around it, centre %.2f .. %.2f\n",
                below, lowest, highest);
    CHECK(below == doctest::Approx(0.5).epsilon(0.2));
    CHECK(highest - lowest < 3.0);
    float_box(Material::Liquid, 2000, 100, lowest, highest, awake);
    CHECK(lowest == doctest::Approx(5));
  }
}

TEST_CASE("World::add_body and set_body_pose refuse bad input, naming the field and the value") {
  World w(test_def({16, 16, 16}, kRules));
  BodyDef def;
  def.half_extents.y = -1;
  check_has(error_of<InvalidArgument>([&] { w.add_body(def); }), {"BodyDef::half_extents.y = -1"});
  def = {};
  def.radius = 1e9;
  def.shape = BodyShape::Sphere;
  check_has(error_of<InvalidArgument>([&] { w.add_body(def); }), {"BodyDef::radius = 1e+09", "64"});
  def = {};
  def.density = std::nan("");
  check_has(error_of<InvalidArgument>([&] { w.add_body(def); }), {"BodyDef::density = nan"});
  def = {};
  def.shape = BodyShape(9);
  check_has(error_of<InvalidArgument>([&] { w.add_body(def); }), {"BodyDef::shape = 9"});
  def = {};
  def.pose.orientation = {0, 0, 0, 0};
  check_has(error_of<InvalidArgument>([&] { w.add_body(def); }), {"orientation = (0, 0, 0, 0)"});
  def = {};
  def.pose.velocity = {5000, 0, 0};
  check_has(error_of<InvalidArgument>([&] { w.add_body(def); }), {"velocity = (5000, 0, 0)", "at most 4096"});
  const BodyId id = w.add_body(BodyDef{});
  BodyPose pose;
  pose.position.x = INFINITY;
  check_has(error_of<InvalidArgument>([&] { w.set_body_pose(id, pose); }), {"pose.position = (inf, 0, 0)"});
  check_has(error_of<InvalidArgument>([&] { w.set_body_pose(id + 5, BodyPose{}); }),
            {"no body " + std::to_string(id + 5)});
  check_has(error_of<InvalidArgument>([&] { w.remove_body(id + 5); }), {"no body"});

  WorldDef solid_bodies = test_def({16, 16, 16}, kRules);
  solid_bodies.body_material = Material::Granular;
  World g(solid_bodies);
  check_has(error_of<InvalidArgument>([&] { g.add_body(BodyDef{}); }),
            {"WorldDef::body_material = 2", "granular", "static"});
  solid_bodies.cell_metres = 0;
  check_has(error_of<InvalidArgument>([&] { World bad(solid_bodies); }), {"WorldDef::cell_metres = 0"});
}

TEST_CASE("a ball rolled across a bed leaves a groove, and stops sooner in deeper sand") {
  // A ball of 1,400 kg/m^3 settles into a bed of sand and is launched at 1 m/s along x; OwnPhysics
  // moves it. Over a bed shallower than it sinks, it rests on the floor and ploughs less sand.
  auto roll = [](int depth, double speed, double& groove) {
    World w(test_def({96, 32, 32}, kRules));
    w.paint(Box{{0, 0, 0}, {96, 32, depth}}, Material::Granular);
    w.step(20);
    const MaterialCounts before = w.count();
    BodyDef def;
    def.shape = BodyShape::Sphere;
    def.radius = 4;
    def.density = 1400;
    def.pose.position = {10, 16, depth + 4.0};
    OwnPhysics ball(w, w.add_body(def), 4);
    for (int t = 0; t < 60; ++t) ball.tick();  // it settles into the bed
    ball.velocity = {speed, 0, 0};
    for (int t = 0; t < 120; ++t) ball.tick();
    const double travelled = ball.pose.position.x - 10;
    // The groove: the bed's top along the track, behind the ball, against the bed 8 cells beside it.
    auto top = [&](int x, int y) {
      const std::vector<std::uint8_t> column = w.read_region(Box{{x, y, 0}, {x + 1, y + 1, 32}});
      int h = 0;
      for (int z = 0; z < 32; ++z)
        if (column[std::size_t(z)] == to_cell(Material::Granular)) h = z + 1;
      return h;
    };
    groove = 0;
    const int from = 10, to = std::max(from + 1, int(ball.pose.position.x));
    for (int x = from; x < to; ++x) groove += double(top(x, 2) - top(x, 16)) / (to - from);
    CHECK(w.count()[to_cell(Material::Granular)] == before[to_cell(Material::Granular)]);
    return travelled;
  };
  double shallow_groove = 0, deep_groove = 0;
  const double shallow = roll(3, 1.0, shallow_groove), deep = roll(14, 1.0, deep_groove);
  std::printf(
      "ball at 1 m/s: %.1f cells over a 3-cell bed (groove %.2f cells deep), %.1f over a 14-cell bed "
      "(groove %.2f)\n",
      shallow, shallow_groove, deep, deep_groove);
  CHECK(deep < shallow);
  CHECK(shallow_groove >= 0.5);
  CHECK(deep_groove >= 0.5);
}

TEST_CASE("water closes behind a crate pushed through a pool") {
  // A crate half in a pool 12 cells deep is pushed 20 cells along x at half a cell a tick, then held.
  // The trench it cuts (20 cells long, 8 wide, 4 deep: 640 cells) must close: the stamp fills the
  // cells it leaves from the water's surface, and the rules level the surface. Counted: the cells
  // below the water line, behind the crate, that hold no water.
  World w(test_def({96, 32, 32}, kRules));
  w.paint(Box{{0, 0, 0}, {96, 32, 12}}, Material::Liquid);
  BodyDef def;
  def.shape = BodyShape::Box;
  def.half_extents = {4, 4, 4};
  def.pose.position = {20, 16, 12};
  def.pose.velocity = {0.5, 0, 0};
  const BodyId crate = w.add_body(def);
  const std::uint64_t water = cells_of(w, Material::Liquid);
  auto missing_behind = [&] {
    const int behind = int(w.body_pose(crate).position.x) - 5;
    const std::vector<std::uint8_t> cells = w.read_region(Box{{0, 0, 0}, {behind, 32, 12}});
    return std::count(cells.begin(), cells.end(), to_cell(Material::Void));
  };
  w.step(40);
  BodyPose held = w.body_pose(crate);
  held.velocity = {0, 0, 0};
  w.set_body_pose(crate, held);
  const auto stopped = missing_behind();
  w.step(40);
  const auto later = missing_behind();
  std::printf(
      "crate pushed 20 cells through water: %td cells of the 640-cell trench without water when it stops, "
      "%td 40 ticks later\n",
      stopped, later);
  CHECK(cells_of(w, Material::Liquid) == water);
  CHECK(later < stopped);
  CHECK(later < 64);  // more than 90% of the trench closed
}

TEST_CASE("a capsule walked through a dune leaves it whole") {
  // An upright capsule (a character) walks at 0.3 m/s straight through a dune of sand and out.
  World w(test_def({96, 32, 40}, kRules));
  w.paint(Box{{40, 0, 0}, {56, 32, 16}}, Material::Granular);
  w.step(150);  // the ridge slumps into a dune
  auto profile = [&] {
    std::vector<int> height(96, 0);
    const std::vector<std::uint8_t> slice = w.read_region(Box{{0, 24, 0}, {96, 25, 40}});
    for (int z = 0; z < 40; ++z)
      for (int x = 0; x < 96; ++x)
        if (slice[std::size_t(z * 96 + x)] == to_cell(Material::Granular)) height[std::size_t(x)] = z + 1;
    return height;
  };
  const std::vector<int> before = profile();
  const std::uint64_t sand = w.count()[to_cell(Material::Granular)];
  BodyDef def;
  def.shape = BodyShape::Capsule;
  def.radius = 3;
  def.half_length = 6;
  def.pose.position = {10, 8, 10};
  def.pose.velocity = {2, 0, 0};  // 2 cells a tick
  const BodyId walker = w.add_body(def);
  w.step(44);  // through the dune and out of it
  CHECK(w.body_pose(walker).position.x == doctest::Approx(98));
  w.remove_body(walker);
  w.step(60);
  CHECK(w.count()[to_cell(Material::Granular)] == sand);
  // Far from the track (y = 24 against a capsule at y = 8 of radius 3), the dune stands as it stood.
  const std::vector<int> after = profile();
  const int crest_before = *std::max_element(before.begin(), before.end());
  const int crest_after = *std::max_element(after.begin(), after.end());
  std::printf("dune crest at y = 24: %d cells before the walk, %d after\n", crest_before, crest_after);
  CHECK(crest_after >= crest_before - 1);
  // Along the track the sand is still there: the walk pushed it aside, not away.
  const std::vector<std::uint8_t> track = w.read_region(Box{{30, 0, 0}, {66, 17, 40}});
  const auto track_sand = std::count(track.begin(), track.end(), to_cell(Material::Granular));
  std::printf("sand in the track's half of the dune: %lld cells of %llu\n", static_cast<long long>(track_sand),
              static_cast<unsigned long long>(sand));
  CHECK(double(track_sand) > 0.4 * double(sand));
}

TEST_CASE("bodies at the grid's edge, leaving it, jumping far and overlapping keep every cell") {
  World w(test_def({32, 32, 32}, kRules));
  w.paint(Box{{0, 0, 0}, {32, 32, 8}}, Material::Granular);
  w.step(10);
  const std::uint64_t sand = cells_of(w, Material::Granular);
  BodyDef def;
  def.half_extents = {3, 3, 3};
  def.pose.position = {1, 16, 8};  // half of it past x = 0
  const BodyId edge = w.add_body(def);
  def.pose.position = {16, 16, 10};
  const BodyId a = w.add_body(def);
  def.pose.position = {19, 16, 10};  // overlapping a by half
  const BodyId b = w.add_body(def);
  w.step(1);
  CHECK(w.body_sand(edge).cells == 4 * 6 * 6);  // the cells of x = 0 .. 3 only
  CHECK(w.body_sand(a).cells == 216);
  CHECK(w.body_sand(b).cells == 216 - 108);  // b does not take a's cells...
  CHECK(w.body_sand(b).blocked == 108);      // ...it reports them blocked
  CHECK(cells_of(w, Material::State7) == std::uint64_t(144 + 216 + 108));
  // The edge body leaves the grid, a jumps far across it, b takes the cells a left.
  BodyPose pose = w.body_pose(edge);
  pose.position.x = -20;
  w.set_body_pose(edge, pose);
  pose = w.body_pose(a);
  pose.position = {16, 28, 20};
  w.set_body_pose(a, pose);
  w.step(1);
  CHECK(w.body_sand(edge).cells == 0);
  CHECK(w.body_sand(a).cells == 216);
  CHECK(w.body_sand(b).cells == 216);
  CHECK(cells_of(w, Material::State7) == 432);
  CHECK(cells_of(w, Material::Granular) == sand);
  w.remove_body(a);
  w.remove_body(b);
  w.remove_body(edge);
  CHECK(cells_of(w, Material::State7) == 0);
  CHECK(cells_of(w, Material::Granular) == sand);
}
