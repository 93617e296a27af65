#include "scene_runner.hpp"

#include <chrono>
#include <cstdio>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "progress_bar.hpp"

namespace granular::cli {

void add_world_options(CLI::App& command, WorldOptions& o) {
  command.add_option("-s,--scene", o.scene, "scene name (see assets/scenes), scene .json, or a .raw/.vox grid file")
      ->capture_default_str();
  command.add_option("-n,--size", o.size, "scene size N (0 = the scene's default)")->capture_default_str();
  command.add_option("--rules", o.rules, "rule set: inertial, inertial-24, isotropic, d4 or paper")->capture_default_str();
  command.add_option("--backend", o.backend, "compute backend")
      ->check(CLI::IsMember({"auto", "cpu", "cuda"}))
      ->capture_default_str();
  command.add_option("-j,--threads", o.threads, "CPU threads (0 = all hardware threads)")->capture_default_str();
  command.add_option("--seed", o.seed, "seed of every random choice")->capture_default_str();
  command.add_flag("--no-lut-cache", o.no_lut_cache, "build the transition table even when it is cached");
  command.add_flag("--dense", o.dense, "step every block every tick (no sleeping bricks; same result, for comparison)");
}

PreparedWorld prepare_world(const WorldOptions& o) {
  WorldDef def;
  def.rules = o.rules;
  def.seed = o.seed;
  def.threads = o.threads;
  def.use_lut_cache = !o.no_lut_cache;
  def.sparse = !o.dense;
  def.backend = o.backend == "cpu" ? BackendKind::Cpu : o.backend == "cuda" ? BackendKind::Cuda : BackendKind::Auto;
  PreparedWorld p;
  const std::filesystem::path as_path(o.scene);
  const auto ext = as_path.extension().string();
  if (ext == ".raw" || ext == ".vox") {
    if (o.size != 0) throw InvalidArgument("--size applies to scenes, not to the grid file " + o.scene);
    p.scene_name = o.scene;
    p.world = std::make_unique<World>(def, load_grid(as_path));
  } else {
    const Scene scene = load_scene(find_scene(o.scene));
    SceneInstance instance = instantiate(scene, o.size);
    p.scene_name = scene.name;
    p.n = instance.n;
    p.emitters = std::move(instance.emitters);
    p.world = std::make_unique<World>(def, instance.grid);
  }
  for (const auto& notice : p.world->notices()) std::fprintf(stderr, "notice: %s\n", notice.c_str());
  return p;
}

double run_ticks(PreparedWorld& p, std::uint64_t ticks, bool progress) {
  ProgressBar bar("ticks", ticks, progress);
  // Without emitters, step in chunks so the per-call overhead vanishes; with them, one tick per call.
  const std::uint64_t chunk = p.emitters.empty() ? std::max<std::uint64_t>(1, ticks / 200) : 1;
  double seconds = 0;
  for (std::uint64_t done = 0; done < ticks;) {
    const int n = int(std::min<std::uint64_t>(chunk, ticks - done));
    if (!p.emitters.empty()) run_emitters(*p.world, p.emitters);
    const auto start = std::chrono::steady_clock::now();
    p.world->step(n);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    p.brick_ticks += p.world->activity().brick_ticks;
    p.cell_ticks += p.world->activity().cell_ticks;
    done += std::uint64_t(n);
    bar.update(done);
  }
  bar.finish();
  return seconds;
}

}  // namespace granular::cli
