#include "scene_runner.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>

#include "choices_text.hpp"
#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/world_snapshot.hpp"
#include "number_option.hpp"

namespace granular::cli {

void add_world_options(CLI::App& command, WorldOptions& o) {
  command
      .add_option("-s,--scene", o.scene,
                  "scene name (see assets/scenes), scene .json, a .raw/.vox grid file, or a .gsnap snapshot (continues "
                  "from its tick under its rules and seed)")
      ->capture_default_str();
  add_number_option(command, "-n,--size", o.size,
                    {1, std::uint64_t(kMaxGridExtent), "omit --size for the scene's default N"},
                    "scene size N (omit it for the scene's default_n)")
      ->default_str("the scene's default");
  command.add_option("--rules", o.rules, "rule set: " + rule_preset_choices())
      ->capture_default_str()
      ->each([&o](const std::string&) { o.rules_given = true; });
  command.add_option("--backend", o.backend, "compute backend")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}))
      ->capture_default_str();
  add_number_option(command, "-j,--threads", o.threads, threads_range(),
                    "CPU threads (0 = all hardware threads)");
  add_number_option(command, "--seed", o.seed, {}, "seed of every random choice")->each([&o](const std::string&) {
    o.seed_given = true;
  });
  command.add_flag("--no-lut-cache", o.no_lut_cache, "build the transition table even when it is cached");
  command.add_flag("--dense", o.dense, "step every block every tick (no sleeping bricks; same result, for comparison)");
  command
      .add_option("--dense-fraction", o.dense_fraction,
                  "CUDA sparse stepping: above this fraction of awake bricks a step runs the dense kernels, recording "
                  "the sleeping bricks (same result); 0 always, 1 never; default: the rule set's "
                  "(WorldDef::cuda.dense_fraction, or motion_dense_fraction with a motion model)")
      ->check(CLI::Range(0.0, 1.0));
}

void add_ticks_option(CLI::App& command, std::uint64_t& ticks, const std::string& description) {
  add_number_option(command, "-t,--ticks", ticks, {0, kMaxTicks, ""}, description);
}

WorldSource load_world_source(const WorldOptions& o, double bytes_per_cell) {
  WorldSource source;
  WorldDef& def = source.def;
  def.rules = o.rules;
  def.seed = o.seed;
  def.threads = o.threads;
  def.use_lut_cache = !o.no_lut_cache;
  def.sparse = !o.dense;
  // CLI::Range lets NaN through (every comparison with it is false).
  if (o.dense_fraction && std::isnan(*o.dense_fraction))
    throw InvalidArgument("--dense-fraction nan: is not a number (expected a fraction from 0 to 1)");
  if (o.dense_fraction) def.cuda.dense_fraction = def.cuda.motion_dense_fraction = *o.dense_fraction;
  def.backend = o.backend == "cpu" ? BackendKind::Cpu : o.backend == "cuda" ? BackendKind::Cuda : BackendKind::Auto;
  const std::filesystem::path as_path(o.scene);
  if (is_snapshot_file(as_path)) {
    if (o.size != 0) throw InvalidArgument("--size applies to scenes, not to the snapshot " + o.scene);
    source.scene_name = o.scene;
    WorldSnapshot snapshot = load_snapshot(as_path);
    if (o.rules_given && o.rules != snapshot.rules)
      throw InvalidArgument("--rules " + o.rules + ": the snapshot " + o.scene + " continues under its own rules, '" +
                            snapshot.rules + "' (omit --rules)");
    if (o.seed_given && o.seed != snapshot.seed)
      throw InvalidArgument("--seed " + std::to_string(o.seed) + ": the snapshot " + o.scene +
                            " continues under its own seed, " + std::to_string(snapshot.seed) + " (omit --seed)");
    def.rules = snapshot.rules;
    // The snapshot's cells are allocated already; the world's grid and its backend's copy are not.
    check_grid_size(snapshot.size, o.scene, bytes_per_cell, kWorldOverheadBytes);
    source.snapshot_tick = snapshot.tick;
    source.snapshot = std::move(snapshot);
  } else if (is_grid_file(as_path)) {
    if (o.size != 0) throw InvalidArgument("--size applies to scenes, not to the grid file " + o.scene);
    source.scene_name = o.scene;
    source.grid = load_grid(as_path, &source.notices);
    // The file's grid is allocated already: what is left to allocate is the rest of the need.
    check_grid_size(source.grid.size(), o.scene, bytes_per_cell - 1.0, kWorldOverheadBytes);
  } else {
    const Scene scene = load_scene(find_scene(o.scene));
    const int n = o.size != 0 ? o.size : scene.default_n;
    const std::string what = "scene '" + scene.name + "' at N=" + std::to_string(n);
    if (n >= scene.min_n) check_grid_size(scene_size(scene, n), what, bytes_per_cell, kWorldOverheadBytes);
    SceneInstance instance = instantiate(scene, n);
    source.scene_name = scene.name;
    source.n = instance.n;
    source.emitters = std::move(instance.emitters);
    source.grid = std::move(instance.grid);
  }
  return source;
}

PreparedWorld prepare_world(const WorldOptions& o, double bytes_per_cell) {
  WorldSource source = load_world_source(o, bytes_per_cell);
  for (const auto& notice : source.notices) std::fprintf(stderr, "notice: %s\n", notice.c_str());
  PreparedWorld p;
  p.scene_name = std::move(source.scene_name);
  p.n = source.n;
  p.snapshot_tick = source.snapshot_tick;
  p.emitters = std::move(source.emitters);
  p.world = source.snapshot ? std::make_unique<World>(source.def, *source.snapshot)
                            : std::make_unique<World>(source.def, source.grid);
  for (const auto& notice : p.world->notices()) std::fprintf(stderr, "notice: %s\n", notice.c_str());
  return p;
}

int tick_chunk(std::uint64_t total, std::uint64_t done, bool per_tick) {
  if (done >= total) return 0;
  const std::uint64_t chunk = per_tick ? 1 : std::max<std::uint64_t>(1, total / 200);
  return int(std::min({chunk, total - done, std::uint64_t(INT_MAX)}));
}

double run_ticks(PreparedWorld& p, std::uint64_t ticks, bool progress) {
  return step_world(*p.world, p.emitters, ticks, progress, p.poured, [&p] {
    p.brick_ticks += p.world->activity().brick_ticks;
    p.cell_ticks += p.world->activity().cell_ticks;
  });
}

}  // namespace granular::cli
