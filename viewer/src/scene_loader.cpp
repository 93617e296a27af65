#include "scene_loader.hpp"

#include <filesystem>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/vox_io.hpp"

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
  const std::string extension = as_path.extension().string();
  if (extension == ".raw" || extension == ".vox") {
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

}  // namespace viewer
