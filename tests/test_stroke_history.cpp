/// @file test_stroke_history.cpp
/// Undo and redo of strokes on a world that keeps stepping: undo puts back the exact world at the
/// stroke's start (hash, tick, tool calls: every cell byte), and the world continues from there as
/// it did then; redo puts back the stroke's end; a change after an undo or a new stroke forgets the
/// redo list; the memory bound drops the oldest strokes. Sparse and dense stepping.

#include <doctest/doctest.h>

#include <vector>

#include "granular/errors.hpp"
#include "granular/stroke_history.hpp"
#include "granular/world.hpp"
#include "test_support.hpp"
#include "tool_session.hpp"

using namespace granular;
using granular::test::check_has;
using granular::test::error_of;
using granular::test::fluid_scene;
using granular::test::play;
using granular::test::play_alike;
using granular::test::test_def;

namespace {

const Int3 kSize{40, 36, 44};

/// What identifies a world's state: its hash, tick and tool calls.
struct State {
  std::uint64_t hash, tick, tool_calls;
  bool operator==(const State&) const = default;
};
State state_of(const World& w) { return {w.hash(), w.tick(), w.tool_calls()}; }

/// One stroke: a dig held for `ticks` ticks (the world steps meanwhile), then released.
void stroke(World& w, StrokeHistory& history, int ticks, double x) {
  history.begin_stroke();
  for (int i = 0; i < ticks; ++i) {
    w.dig(Sphere{{x, 18.0, 24.0}, 5.0});
    w.pour({x, 10.0, 38.0}, 3.0, Material::Granular, 12);
    w.step(1);
  }
  history.end_stroke();
}

}  // namespace

TEST_CASE("history: undo restores the world at the stroke's start exactly, and it continues as it did then") {
  for (const bool sparse : {true, false}) {
    CAPTURE(sparse);
    WorldDef def = test_def(kSize, "inertial-24", 2, 3);
    def.sparse = sparse;
    World world(def, fluid_scene(kSize));
    StrokeHistory history(world);
    CHECK_FALSE(history.undo());
    play(world, 12);
    const State start = state_of(world);
    const WorldSnapshot at_start = world.capture();
    stroke(world, history, 6, 20.0);
    const State end = state_of(world);
    CHECK(history.undo_count() == 1);
    CHECK(history.bytes() > 0);
    CHECK(history.checkpoint_bytes() == std::uint64_t(kSize.x * kSize.y * kSize.z));
    play(world, 9);  // the world steps on after the stroke; undo rewinds that too
    const auto undone = history.undo();
    REQUIRE(undone);
    CHECK(undone->tick == start.tick);
    CHECK(undone->bricks > 0);
    CHECK(undone->strokes_left == 0);
    CHECK(state_of(world) == start);
    CHECK(history.undo_count() == 0);
    CHECK(history.redo_count() == 1);
    const auto redone = history.redo();
    REQUIRE(redone);
    CHECK(redone->tick == end.tick);
    CHECK(state_of(world) == end);  // the stroke's end, not the ticks played after it
    REQUIRE(history.undo());
    CHECK(state_of(world) == start);

    // From the undo on, the world steps as it did from the stroke's start.
    World reference(def, at_start);
    play_alike(world, reference, 20);
    // Which forgot the redo list; undo goes back to the stroke's start again.
    CHECK(history.redo_count() == 0);
    CHECK_FALSE(history.redo());
    CHECK(history.undo_count() == 1);
    REQUIRE(history.undo());
    CHECK(state_of(world) == start);
  }
}

TEST_CASE("history: undo and redo walk back and forth over several strokes; a new stroke forgets the redo list") {
  World world(test_def(kSize, "inertial-24", 2, 5), fluid_scene(kSize));
  StrokeHistory history(world);
  std::vector<State> starts, ends;
  for (int k = 0; k < 3; ++k) {
    play(world, 4);
    starts.push_back(state_of(world));
    stroke(world, history, 3 + k, 10.0 + 8 * k);
    ends.push_back(state_of(world));
  }
  play(world, 5);
  CHECK(history.undo_count() == 3);
  for (int k = 2; k >= 0; --k) {
    REQUIRE(history.undo());
    CHECK(state_of(world) == starts[std::size_t(k)]);
  }
  CHECK_FALSE(history.undo());
  CHECK(history.redo_count() == 3);
  for (int k = 0; k < 3; ++k) {
    const auto redone = history.redo();
    REQUIRE(redone);
    CHECK(redone->strokes_left == std::size_t(2 - k));
    CHECK(state_of(world) == ends[std::size_t(k)]);
  }
  CHECK_FALSE(history.redo());
  REQUIRE(history.undo());
  REQUIRE(history.undo());
  CHECK(state_of(world) == starts[1]);
  stroke(world, history, 2, 30.0);  // a new stroke in the place of the second: what could be redone is gone
  CHECK(history.redo_count() == 0);
  CHECK(history.undo_count() == 2);
  REQUIRE(history.undo());
  CHECK(state_of(world) == starts[1]);
  REQUIRE(history.undo());
  CHECK(state_of(world) == starts[0]);
}

TEST_CASE("history: a stroke in which nothing happened is no stroke; an open stroke ends before an undo") {
  World world(test_def(kSize, "inertial-24", 2, 5), fluid_scene(kSize));
  StrokeHistory history(world);
  history.begin_stroke();
  history.end_stroke();
  CHECK(history.undo_count() == 0);
  const State start = state_of(world);
  history.begin_stroke();
  world.dig(Sphere{{20.0, 18.0, 30.0}, 6.0});
  world.step(2);
  CHECK(history.stroke_open());
  CHECK(history.undo_count() == 1);
  REQUIRE(history.undo());
  CHECK_FALSE(history.stroke_open());
  CHECK(state_of(world) == start);
}

TEST_CASE("history: the memory bound drops the oldest strokes first") {
  // The same eight strokes on two equal worlds: the first history keeps them all and says how much
  // three of them take, the second keeps only that much.
  const auto play_strokes = [](World& world, StrokeHistory& history, std::vector<State>& starts,
                               std::vector<std::uint64_t>& bytes) {
    for (int k = 0; k < 8; ++k) {
      play(world, 2);
      starts.push_back(state_of(world));
      stroke(world, history, 3, 8.0 + 3 * k);
      bytes.push_back(history.bytes());
    }
  };
  World unbounded_world(test_def(kSize, "inertial-24", 2, 5), fluid_scene(kSize));
  StrokeHistory unbounded(unbounded_world);
  std::vector<State> starts;
  std::vector<std::uint64_t> unbounded_bytes;
  play_strokes(unbounded_world, unbounded, starts, unbounded_bytes);
  CHECK(unbounded.undo_count() == 8);

  World world(test_def(kSize, "inertial-24", 2, 5), fluid_scene(kSize));
  StrokeHistory history(world, unbounded_bytes[2]);
  std::vector<State> bounded_starts;
  std::vector<std::uint64_t> bounded_bytes;
  play_strokes(world, history, bounded_starts, bounded_bytes);
  CHECK(bounded_starts == starts);
  for (const std::uint64_t b : bounded_bytes) CHECK(b <= history.max_bytes());
  const std::size_t kept = history.undo_count();
  CHECK(kept >= 1);
  CHECK(kept < 8);
  for (std::size_t k = 0; k < kept; ++k) {
    REQUIRE(history.undo());
    CHECK(state_of(world) == starts[8 - 1 - k]);  // the newest strokes are the ones kept
  }
  CHECK_FALSE(history.undo());
  check_has(error_of<InvalidArgument>([&] { StrokeHistory none(world, 0); }), {"max_bytes = 0"});
}

TEST_CASE("history: a stroke that changed no cell still rewinds its ticks and tool calls") {
  World world(test_def({24, 24, 24}, "inertial-24", 2, 5));
  world.paint(Box{{0, 0, 0}, {24, 24, 2}}, Material::Solid);
  StrokeHistory history(world);
  world.step(3);
  const State start = state_of(world);
  history.begin_stroke();
  world.dig(Sphere{{12.0, 12.0, 12.0}, 3.0});  // air only: a tool call, no cell
  world.step(5);
  history.end_stroke();
  const State end = state_of(world);
  REQUIRE(history.undo());
  CHECK(state_of(world) == start);
  REQUIRE(history.redo());
  CHECK(state_of(world) == end);
}

TEST_CASE("history: a checkpoint replaced under a history makes it refuse, never undo to other cells") {
  WorldDef def = test_def(kSize, "inertial-24", 2, 3);
  SUBCASE("a second history on the same world") {
    World world(def, fluid_scene(kSize));
    StrokeHistory first(world);
    stroke(world, first, 4, 12.0);
    StrokeHistory second(world);
    stroke(world, second, 4, 28.0);
    check_has(error_of<StateError>([&] { first.undo(); }), {"StrokeHistory::undo", "checkpoint", "another StrokeHistory"});
    // The second history owns the checkpoint now and undoes its stroke exactly.
    const std::uint64_t end_of_stroke = world.hash();
    CHECK(second.undo());
    first.clear();  // forgets its strokes without dropping the second's checkpoint
    CHECK(second.redo());
    CHECK(world.hash() == end_of_stroke);
    // Destroying the stale history leaves the owner's checkpoint alone.
    CHECK(world.checkpoint_bytes() > 0);
  }
  SUBCASE("the game's own take_checkpoint during a stroke") {
    World world(def, fluid_scene(kSize));
    StrokeHistory history(world);
    history.begin_stroke();
    world.dig(Sphere{{20.0, 18.0, 24.0}, 5.0});
    world.step(2);
    world.take_checkpoint();
    world.dig(Sphere{{20.0, 18.0, 30.0}, 4.0});
    check_has(error_of<StateError>([&] { history.end_stroke(); }), {"StrokeHistory::end_stroke", "take_checkpoint"});
    check_has(error_of<StateError>([&] { history.undo(); }), {"StrokeHistory::undo"});
    check_has(error_of<StateError>([&] { history.begin_stroke(); }), {"StrokeHistory::begin_stroke"});
    // clear() starts it again: a new stroke undoes exactly.
    history.clear();
    const std::uint64_t start = world.hash();
    stroke(world, history, 3, 20.0);
    CHECK(history.undo());
    CHECK(world.hash() == start);
  }
  SUBCASE("the game's drop_checkpoint") {
    World world(def, fluid_scene(kSize));
    StrokeHistory history(world);
    stroke(world, history, 3, 20.0);
    world.drop_checkpoint();
    CHECK(world.checkpoint_id() == 0);
    check_has(error_of<StateError>([&] { history.undo(); }), {"StrokeHistory::undo", "drop_checkpoint"});
  }
}
