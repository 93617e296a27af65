/// @file test_body_snapshots.cpp
/// Bodies in snapshots and undo (World::body_states, restore_bodies, the .gsnap body section,
/// StrokeHistory): a world with bodies saved, loaded and stepped on keeps the cells, poses and
/// reports of one that never stopped; a snapshot without bodies stays version 3; an undo of a thrown
/// body takes it out again and a redo puts it back where it was; a body section or body state that
/// is damaged or forged is refused by name, the world unchanged.

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <unistd.h>

#include "body_scene.hpp"
#include "granular/body.hpp"
#include "granular/distributed/distributed_world.hpp"
#include "granular/errors.hpp"
#include "granular/rule_set.hpp"
#include "granular/distributed/local_group.hpp"
#include "granular/stroke_history.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "test_support.hpp"

using namespace granular;
using granular::test::check_has;
using granular::test::error_of;
using granular::test::test_def;

namespace {

/// The scene of test_bodies' conservation test: a bed under water, gas, ten bodies of every shape.
WorldDef scene_def(bool sparse = true) {
  WorldDef def = test_def({48, 48, 40}, "inertial-24-flow", 2, 5);
  def.sparse = sparse;
  return def;
}

/// Gives every body of `w` a heading that depends on the tick and its handle only, so that two
/// worlds driven by it move their bodies alike.
void steer(World& w) {
  for (const BodyId id : w.body_ids()) {
    BodyPose pose = w.body_pose(id);
    const double t = double(w.tick()) * 0.07 + double(id);
    pose.velocity = {0.4 * std::sin(t), 0.4 * std::cos(1.3 * t), 0.3 * std::sin(0.7 * t)};
    if (pose.position.x < 10) pose.velocity.x = 0.4;
    if (pose.position.x > 38) pose.velocity.x = -0.4;
    if (pose.position.y < 10) pose.velocity.y = 0.4;
    if (pose.position.y > 38) pose.velocity.y = -0.4;
    if (pose.position.z < 8) pose.velocity.z = 0.3;
    if (pose.position.z > 30) pose.velocity.z = -0.3;
    w.set_body_pose(id, pose);
  }
}

/// Checks that `a` and `b` hold the same bodies at the same poses with the same reports.
void check_same_bodies(const World& a, const World& b) {
  REQUIRE(a.body_ids() == b.body_ids());
  for (const BodyId id : a.body_ids()) {
    CHECK(a.body_pose(id).position.x == b.body_pose(id).position.x);
    CHECK(a.body_pose(id).position.z == b.body_pose(id).position.z);
    CHECK(a.body_pose(id).orientation.w == b.body_pose(id).orientation.w);
    CHECK(a.body_sand(id).cells == b.body_sand(id).cells);
    CHECK(a.body_sand(id).force.z == b.body_sand(id).force.z);
    CHECK(a.body_sand(id).torque.x == b.body_sand(id).torque.x);
  }
  CHECK(a.body_states().bodies.size() == b.body_states().bodies.size());
}

/// A file in the test's temporary folder.
std::filesystem::path temp_file(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("granular-body-snapshot-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

/// The snapshot of the wandering-bodies scene after 60 ticks, one body removed so that the next
/// handle is past every body's.
WorldSnapshot scene_snapshot(World& w) {
  test::WanderingBodies scene(w);
  for (int t = 0; t < 60; ++t) scene.tick();
  w.remove_body(scene.ids[3]);
  return w.capture();
}

/// Parts of an encoded snapshot with bodies.
struct Encoded {
  std::vector<std::uint8_t> bytes;
  std::size_t body_header = 0;  ///< where the body header starts (after the name)
};

Encoded encoded(const WorldSnapshot& s) {
  Encoded e{encode_snapshot(s), 72 + s.rules.size()};
  return e;
}

void put32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) { std::memcpy(b.data() + at, &v, 4); }
void put64(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v) { std::memcpy(b.data() + at, &v, 8); }

}  // namespace

TEST_CASE("body snapshots: a world with bodies saved, loaded and stepped on keeps the cells, poses and reports of one that never stopped") {
  for (const bool sparse : {true, false}) {
    CAPTURE(sparse);
    World original(scene_def(sparse));
    const WorldSnapshot captured = scene_snapshot(original);
    REQUIRE(captured.bodies.bodies.size() == 9);
    CHECK(captured.bodies.next_id == 11);
    std::uint64_t held = 0;
    for (const BodyState& b : captured.bodies.bodies) held += b.cells.size();
    CHECK(held == original.count()[to_cell(Material::State7)]);

    const auto file = temp_file(sparse ? "bodies-sparse.gsnap" : "bodies-dense.gsnap");
    save_snapshot(captured, file);
    const WorldSnapshot loaded = load_snapshot(file);
    REQUIRE(loaded.bodies.bodies.size() == captured.bodies.bodies.size());
    CHECK(loaded.bodies.next_id == captured.bodies.next_id);
    for (std::size_t i = 0; i < loaded.bodies.bodies.size(); ++i) {
      CHECK(loaded.bodies.bodies[i].id == captured.bodies.bodies[i].id);
      CHECK(loaded.bodies.bodies[i].cells == captured.bodies.bodies[i].cells);
      CHECK(loaded.bodies.bodies[i].def.pose.velocity.y == captured.bodies.bodies[i].def.pose.velocity.y);
      CHECK(loaded.bodies.bodies[i].def.half_extents.z == captured.bodies.bodies[i].def.half_extents.z);
    }
    World continued(scene_def(sparse), loaded);
    World restored(scene_def(sparse));
    restored.add_body(BodyDef{});  // a body of its own, replaced by the snapshot's
    restored.restore(loaded);
    CHECK(restored.body_ids() == original.body_ids());
    for (int t = 0; t < 80; ++t) {
      for (World* w : {&original, &continued, &restored}) {
        steer(*w);
        w->step(1);
      }
      REQUIRE(continued.hash() == original.hash());
      REQUIRE(restored.hash() == original.hash());
    }
    check_same_bodies(original, continued);
    check_same_bodies(original, restored);
    // The next handle is the one the original gives.
    CHECK(continued.add_body(BodyDef{}) == original.add_body(BodyDef{}));
    std::filesystem::remove_all(file.parent_path());
  }
}

TEST_CASE("body snapshots: only a world with bodies is written as version 6; its body header is documented") {
  World plain(scene_def());
  CHECK(encode_snapshot(plain.capture())[4] == kSnapshotVersion);
  World w(scene_def());
  const WorldSnapshot s = scene_snapshot(w);
  const Encoded e = encoded(s);
  CHECK(e.bytes[4] == kBodiesSnapshotVersion);
  std::uint32_t layout = 0, count = 0;
  std::uint64_t body_bytes = 0;
  std::memcpy(&layout, e.bytes.data() + e.body_header, 4);
  std::memcpy(&count, e.bytes.data() + e.body_header + 4, 4);
  std::memcpy(&body_bytes, e.bytes.data() + e.body_header + 8, 8);
  CHECK(layout == kSnapshotVersion);
  CHECK(count == 9);
  std::uint64_t held = 0;
  for (const BodyState& b : s.bodies.bodies) held += b.cells.size();
  CHECK(body_bytes == 8 + 9 * (168 + 8) + 8 * held);
  // Every body removed: no body, but the next handle is kept, so version 6 still.
  for (const BodyId id : w.body_ids()) w.remove_body(id);
  const WorldSnapshot empty = w.capture();
  CHECK(empty.bodies.bodies.empty());
  CHECK(empty.bodies.next_id == 11);
  CHECK(encode_snapshot(empty)[4] == kBodiesSnapshotVersion);
  CHECK(decode_snapshot(encode_snapshot(empty), "empty.gsnap").bodies.next_id == 11);
}

TEST_CASE("body snapshots: a damaged body header or section is a ParseError naming the field") {
  World w(scene_def());
  const WorldSnapshot s = scene_snapshot(w);
  const Encoded e = encoded(s);
  auto refused = [&](std::vector<std::uint8_t> bytes) {
    return error_of<ParseError>([&] { decode_snapshot(bytes, "forged.gsnap"); });
  };
  {
    std::vector<std::uint8_t> b = e.bytes;
    put32(b, e.body_header, 7);
    check_has(refused(b), {"forged.gsnap", "layout", "= 7", "is not 3, 4 or 5"});
  }
  {
    std::vector<std::uint8_t> b = e.bytes;
    put32(b, e.body_header + 4, 5000);
    check_has(refused(b), {"body_count", "5000", "kMaxBodies"});
  }
  {
    std::vector<std::uint8_t> b = e.bytes;
    put64(b, e.body_header + 8, std::uint64_t(1) << 40);
    check_has(refused(b), {"body_bytes", "is outside"});
  }
  {
    std::vector<std::uint8_t> b = e.bytes;
    put64(b, e.body_header + 8, 8 + 9 * (168 + 8) + 8);  // fewer bytes than the bodies hold
    check_has(refused(b), {"forged.gsnap"});
  }
  {
    std::vector<std::uint8_t> b(e.bytes.begin(), e.bytes.begin() + std::ptrdiff_t(e.body_header + 10));
    check_has(refused(b), {"truncated body header", "16 bytes"});
  }
  {
    // One bit of the compressed data flipped: refused by zstd or by the hash, never read as bodies.
    std::vector<std::uint8_t> b = e.bytes;
    b[b.size() - 9] ^= 0x10;
    const std::string message = refused(b);
    CHECK(!message.empty());
  }
  {
    // The body count one lower, the section size to match: the bodies do not fit the section.
    std::vector<std::uint8_t> b = e.bytes;
    put32(b, e.body_header + 4, 8);
    check_has(refused(b), {"forged.gsnap"});
  }
}

TEST_CASE("body snapshots: body states a world cannot hold are refused by name, the world unchanged") {
  World w(scene_def());
  const WorldSnapshot good = scene_snapshot(w);
  World target(scene_def());
  test::WanderingBodies other(target);
  for (int t = 0; t < 5; ++t) other.tick();
  const std::uint64_t before = target.hash();
  const auto ids_before = target.body_ids();
  auto refused = [&](const WorldSnapshot& s) {
    const std::string message = error_of<InvalidArgument>([&] { target.restore(s); });
    CHECK(target.hash() == before);
    CHECK(target.body_ids() == ids_before);
    return message;
  };
  {
    WorldSnapshot s = good;
    s.bodies.bodies[2].id = s.bodies.bodies[1].id;
    check_has(refused(s), {"World::restore", "two bodies have the handle"});
  }
  {
    WorldSnapshot s = good;
    s.bodies.bodies[0].id = 99;
    check_has(refused(s), {"bodies[0] (body 99)", "not one of 1..10", "next_id = 11"});
  }
  {
    WorldSnapshot s = good;
    s.bodies.bodies[1].def.density = -3;
    check_has(refused(s), {"bodies[1]", "BodyDef::density = -3"});
  }
  {
    WorldSnapshot s = good;
    s.bodies.bodies[1].def.pose.velocity.x = std::nan("");
    check_has(refused(s), {"bodies[1]", "velocity"});
  }
  {
    WorldSnapshot s = good;
    s.cells[s.bodies.bodies[4].cells[0]] = to_cell(Material::Granular);
    check_has(refused(s), {"bodies[4]", "cells[0]", "holds material 2", "not WorldDef::body_material 7"});
  }
  {
    WorldSnapshot s = good;
    s.bodies.bodies[5].cells.push_back(s.bodies.bodies[6].cells.back());
    std::sort(s.bodies.bodies[5].cells.begin(), s.bodies.bodies[5].cells.end());
    check_has(refused(s), {"is held by bodies[5] and bodies[6]"});
  }
  {
    WorldSnapshot s = good;
    std::swap(s.bodies.bodies[0].cells[0], s.bodies.bodies[0].cells[1]);
    check_has(refused(s), {"bodies[0]", "cells[1]", "ascending"});
  }
  {
    WorldSnapshot s = good;
    s.bodies.bodies[0].cells.back() = std::uint64_t(48) * 48 * 40;
    check_has(refused(s), {"bodies[0]", "outside the 48x48x40 grid"});
  }
  {
    WorldSnapshot s = good;
    s.bodies.next_id = 0;
    check_has(refused(s), {"next_id = 0"});
  }
  CHECK_NOTHROW(target.restore(good));
  CHECK(target.hash() == w.hash());
}

TEST_CASE("body undo: a thrown body is one stroke; undo takes it out, redo puts it back where the stroke ended") {
  World w(scene_def());
  w.paint(Box{{0, 0, 0}, {48, 48, 12}}, Material::Granular);
  for (int t = 0; t < 4; ++t) w.step(1);
  StrokeHistory history(w);
  const std::uint64_t before = w.hash();
  const std::uint64_t tick_before = w.tick();

  history.begin_stroke();
  BodyDef crate;
  crate.half_extents = {3, 3, 3};
  crate.pose.position = {24, 24, 30};
  crate.pose.velocity = {0, 0, -0.5};
  const BodyId id = w.add_body(crate);
  history.end_stroke();
  CHECK(history.undo_count() == 1);
  for (int t = 0; t < 40; ++t) w.step(1);  // it falls into the bed
  REQUIRE(w.body_pose(id).position.z < 20);
  const std::uint64_t fallen = w.hash();
  const BodyStates landed = w.body_states();

  // The undo goes back over the ticks since, as for a tool's stroke, to before the throw.
  const auto undone = history.undo();
  REQUIRE(undone.has_value());
  CHECK(w.tick() == tick_before);
  CHECK(w.body_ids().empty());
  CHECK(w.hash() == before);
  CHECK(w.count()[to_cell(Material::State7)] == 0);

  // Redo: the world at the stroke's end, the body where it was thrown from, holding no cell yet.
  const auto redone = history.redo();
  REQUIRE(redone.has_value());
  REQUIRE(w.body_ids() == std::vector<BodyId>{id});
  CHECK(w.body_pose(id).position.z == 30);
  CHECK(w.body_pose(id).velocity.z == -0.5);
  CHECK(w.hash() == before);
  for (int t = 0; t < 40; ++t) w.step(1);
  CHECK(w.hash() == fallen);
  CHECK(w.body_states().bodies[0].cells == landed.bodies[0].cells);
  // The handle the next add_body gives is the one after the redone body's, as before the undo.
  CHECK(w.add_body(crate) == id + 1);
}

TEST_CASE("body undo: undoing a dig puts back the bodies the ticks since have moved, cells and poses alike") {
  World w(scene_def());
  test::WanderingBodies scene(w);
  for (int t = 0; t < 10; ++t) scene.tick();
  StrokeHistory history(w);
  const std::uint64_t before = w.hash();
  const BodyStates bodies_before = w.body_states();
  history.begin_stroke();
  w.dig(Sphere{{24, 24, 10}, 5});
  history.end_stroke();
  for (int t = 0; t < 30; ++t) scene.tick();
  REQUIRE(history.undo().has_value());
  CHECK(w.hash() == before);
  const BodyStates after = w.body_states();
  REQUIRE(after.bodies.size() == bodies_before.bodies.size());
  for (std::size_t i = 0; i < after.bodies.size(); ++i) {
    CHECK(after.bodies[i].cells == bodies_before.bodies[i].cells);
    CHECK(after.bodies[i].def.pose.position.x == bodies_before.bodies[i].def.pose.position.x);
  }
  CHECK(history.bytes() > 0);
}

TEST_CASE("body undo: restore_bodies refuses bodies whose cells the grid does not hold") {
  World w(scene_def());
  test::WanderingBodies scene(w);
  for (int t = 0; t < 3; ++t) scene.tick();
  const BodyStates states = w.body_states();
  w.paint(Box{{0, 0, 0}, {48, 48, 40}}, Material::Void);
  check_has(error_of<InvalidArgument>([&] { w.restore_bodies(states); }),
            {"World::restore_bodies", "bodies[0]", "holds material 0"});
  CHECK(w.body_ids() == scene.ids);
}

TEST_CASE("body snapshots: a DistributedWorld refuses a snapshot with bodies, in memory or as a file") {
  World w(scene_def());
  const WorldSnapshot s = scene_snapshot(w);
  const auto file = temp_file("distributed.gsnap");
  save_snapshot(s, file);
  run_local_ranks(1, [&](Communicator& comm) {
    check_has(error_of<InvalidArgument>([&] { DistributedWorld(scene_def(), comm, s); }),
              {"WorldSnapshot::bodies holds 9 bodies"});
    check_has(error_of<ParseError>([&] { DistributedWorld(scene_def(), comm, file); }),
              {"distributed.gsnap", "version 6 holds bodies (9)"});
  });
  std::filesystem::remove_all(file.parent_path());
}

TEST_CASE("body snapshots: the fuzz corpus's version 6 file (built by make_corpus.py, the format as documented) loads") {
  const std::filesystem::path corpus = std::filesystem::path(GRANULAR_TEST_ASSET_DIR) / ".." / "tests" / "fuzz" / "corpus";
  WorldSnapshot s = load_snapshot(corpus / "snapshot-bodies-v6.gsnap");
  REQUIRE(s.bodies.bodies.size() == 1);
  CHECK(s.bodies.next_id == 3);
  const BodyState& b = s.bodies.bodies[0];
  CHECK(b.id == 2);
  CHECK(b.def.shape == BodyShape::Box);
  CHECK(b.def.half_extents.x == 1);
  CHECK(b.def.density == 700);
  CHECK(b.def.pose.position.x == 2);
  CHECK(b.def.pose.velocity.z == -0.25);
  CHECK(b.def.pose.angular_velocity.z == 0.01);
  CHECK(b.cells == std::vector<std::uint64_t>{17, 18});
  s.rule_fingerprint = rule_fingerprint(World(test_def(s.size, "inertial-24", 1)).rules());  // the file's is 0
  World w(test_def(s.size, "inertial-24", 1), s);
  CHECK(w.body_ids() == std::vector<BodyId>{2});
  w.step(3);
  CHECK(w.body_pose(2).position.z == 1.5 - 0.75);
  CHECK(w.count()[to_cell(Material::Granular)] == 12);
}
