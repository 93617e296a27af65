#include "session/scene_loader.hpp"

#include <filesystem>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/vox_io.hpp"
#include "granular/world_snapshot.hpp"

namespace viewer {

granular::BackendKind parse_backend(const std::string& name) {
  if (name == "auto") return granular::BackendKind::Auto;
  if (name == "cpu") return granular::BackendKind::Cpu;
  if (name == "cuda") return granular::BackendKind::Cuda;
  throw granular::InvalidArgument("unknown backend '" + name + "' (expected auto, cpu or cuda)");
}

SandboxWorld load_world(const WorldChoice& choice) {
  granular::WorldDef def;
  def.backend = parse_backend(choice.backend);
  def.rules = choice.rules;
  def.threads = choice.threads;
  SandboxWorld result;
  const std::filesystem::path as_path(choice.scene);
  if (granular::is_snapshot_file(as_path)) {
    const granular::WorldSnapshot snapshot = granular::load_snapshot(as_path);
    if (choice.rules_given && choice.rules != snapshot.rules)
      throw granular::InvalidArgument("--rules " + choice.rules + ": the snapshot " + choice.scene +
                                      " continues under its own rules, '" + snapshot.rules + "' (omit --rules)");
    def.rules = snapshot.rules;
    result.scene_name = choice.scene;
    result.world = std::make_unique<granular::World>(def, snapshot);
    return result;
  }
  if (granular::is_grid_file(as_path)) {
    result.scene_name = choice.scene;
    result.world = std::make_unique<granular::World>(def, granular::load_grid(as_path));
    return result;
  }
  const granular::Scene scene = granular::load_scene(granular::find_scene(choice.scene));
  granular::SceneInstance instance = granular::instantiate(scene, choice.size);
  result.scene_name = scene.name;
  result.n = instance.n;
  result.emitters = std::move(instance.emitters);
  result.world = std::make_unique<granular::World>(def, instance.grid);
  return result;
}

bool is_world_file(const std::string& path) {
  return granular::is_grid_file(path) || granular::is_snapshot_file(path);
}

}  // namespace viewer
