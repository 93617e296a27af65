/// @file test_world_files.cpp
/// The sandbox's files and history without a window: a save line names the state a load line gives
/// back, load_world takes snapshots and grid files in any case (a snapshot under its own rules),
/// the options' snapshot file, --load and their conflicts, the history's HUD and stdout lines, and
/// emitters that stay still while the world is paused.

#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/extend/hex.hpp"
#include "granular/stroke_history.hpp"
#include "granular/world.hpp"
#include "session/history_lines.hpp"
#include "session/sandbox_options.hpp"
#include "session/sandbox_tools.hpp"
#include "session/scene_loader.hpp"
#include "session/world_files.hpp"

using namespace viewer;

namespace {

/// A folder of this test process's own.
std::filesystem::path folder() {
  const auto dir = std::filesystem::temp_directory_path() / ("viewer-world-files-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

WorldChoice cpu_choice(const std::string& scene) {
  WorldChoice choice;
  choice.scene = scene;
  choice.backend = "cpu";
  choice.threads = 2;
  return choice;
}

}  // namespace

TEST_CASE("files: a saved world loads back with the tick and hash its save line names") {
  WorldChoice choice = cpu_choice("dam_break");
  choice.size = 24;
  SandboxWorld sandbox = load_world(choice);
  sandbox.world->step(9);
  const std::string path = (folder() / "Saved.GSNAP").string();
  const std::string saved = save_world(*sandbox.world, path);
  const std::string state = "(" + std::to_string(24 * 6 * 15) + " cells, tick 9, hash " + granular::hex64(sandbox.world->hash()) + ")";
  CHECK(saved == "saved: " + path + " " + state);
  CHECK(is_world_file(path));
  const SandboxWorld loaded = load_world(cpu_choice(path));
  CHECK(loaded.scene_name == path);
  CHECK(loaded.n == 0);
  CHECK(loaded.emitters.empty());
  CHECK(loaded_line(*loaded.world, path) == "loaded: " + path + " " + state);

  WorldChoice paper = cpu_choice(path);
  paper.rules = "paper";
  paper.rules_given = true;
  CHECK_THROWS_AS(load_world(paper), granular::InvalidArgument);
  paper.rules_given = false;  // the default rules' name, not chosen: the snapshot's rules win
  REQUIRE(sandbox.world->rules().name != "paper");
  CHECK(load_world(paper).world->rules().name == sandbox.world->rules().name);

  const std::string grid = (folder() / "grid.RAW").string();
  granular::save_raw(sandbox.world->read_grid(), grid);
  CHECK(is_world_file(grid));
  CHECK(load_world(cpu_choice(grid)).world->size() == sandbox.world->size());
  CHECK_FALSE(is_world_file("notes.txt"));
  CHECK_FALSE(is_world_file("pile"));
}

TEST_CASE("files: --save and --load choose the snapshot file and the start; conflicts are errors") {
  SandboxOptions options;
  CHECK(snapshot_file(options) == kDefaultSnapshotFile);
  CHECK(start_choice(options).scene == "bowl");
  options.save = (folder() / "mine.gsnap").string();
  options.load = "start.gsnap";
  CHECK(snapshot_file(options) == options.save);
  CHECK(start_choice(options).scene == "start.gsnap");
  CHECK_NOTHROW(validate(options));
  options.scene_given = true;
  CHECK_THROWS_AS(validate(options), std::invalid_argument);
  options.scene_given = false;
  options.load = "start.raw";
  CHECK_THROWS_AS(validate(options), std::invalid_argument);
  options.load.clear();
  options.save = "mine.png";
  CHECK_THROWS_AS(validate(options), granular::InvalidArgument);
  options.save.clear();
  options.undo_mib = 0;
  CHECK_THROWS_AS(validate(options), std::invalid_argument);
}

TEST_CASE("files: the history's HUD line and the undo and redo lines") {
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {32, 32, 32};
  granular::World world(def);
  world.paint(granular::Box{{0, 0, 0}, {32, 32, 2}}, granular::Material::Solid);
  granular::StrokeHistory history(world, std::uint64_t(64) << 20);
  CHECK(history_line(history) == "undo: 0 strokes, 0 bytes of 64 MiB");
  CHECK(undo_line(history.undo(), world) == "undo: nothing to undo");
  const std::string before = "tick 0, hash " + granular::hex64(world.hash());
  history.begin_stroke();
  world.dig(granular::Sphere{{16, 16, 1}, 4});
  world.step(3);
  history.end_stroke();
  const std::string after = "tick 3, hash " + granular::hex64(world.hash());
  CHECK(history_line(history).rfind("undo: 1 stroke, ", 0) == 0);
  CHECK(history_line(history).find(" of 64 MiB, checkpoint 32768 bytes") != std::string::npos);
  CHECK(undo_line(history.undo(), world) == "undo: " + before + " (0 more to undo; paused, Ctrl+Shift+Z redoes)");
  CHECK(history_line(history).find("undo: 0 strokes (1 to redo)") == 0);
  CHECK(redo_line(history.redo(), world) == "redo: " + after + " (0 more to redo)");
  CHECK(redo_line(history.redo(), world) == "redo: nothing to redo");
}

TEST_CASE("tools: the scene's emitters pour only while the world runs") {
  granular::WorldDef def;
  def.backend = granular::BackendKind::Cpu;
  def.size = {24, 24, 24};
  granular::World world(def);
  granular::Emitter emitter;
  emitter.center = {12, 12, 18};
  emitter.radius = 3;
  emitter.rate = 5;
  emitter.stop = UINT64_MAX;
  ToolSubsystem tools(world, {emitter});
  bool running = false;
  tools.set_running([&] { return running; });
  tools.fixed_update(1.0 / 60);
  CHECK(world.count()[granular::to_cell(granular::Material::Granular)] == 0);
  running = true;
  tools.fixed_update(1.0 / 60);
  CHECK(world.count()[granular::to_cell(granular::Material::Granular)] == 5);
}
