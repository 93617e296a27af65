#pragma once
/// @file scene_loader.hpp
/// Makes the sandbox's World from a scene name (assets/scenes) or grid file, a size and a backend.

#include <memory>
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "granular/world.hpp"

namespace viewer {

/// What defines the sandbox's world.
struct WorldChoice {
  std::string scene = "bowl";    ///< scene name, scene .json path, or .raw/.vox grid file
  int size = 0;                  ///< scene size parameter N (0: the scene's default)
  std::string backend = "auto";  ///< auto, cpu or cuda
  std::string rules = granular::WorldDef{}.rules;  ///< rule-set preset (the library's default)
  int threads = 0;               ///< CPU threads (0: all)
};

/// A world with its scene's emitters.
struct SandboxWorld {
  std::string scene_name;                  ///< the scene (or grid file) it came from
  int n = 0;                               ///< size parameter used (0 for grid files)
  std::vector<granular::Emitter> emitters; ///< the scene's emitters, in cells
  std::unique_ptr<granular::World> world;  ///< the world
};

/// Builds the world; throws granular::Error (InvalidArgument, ParseError, BackendError...) with the
/// library's actionable message on bad input.
SandboxWorld load_world(const WorldChoice& choice);

/// Parses "auto", "cpu" or "cuda"; throws granular::InvalidArgument otherwise.
granular::BackendKind parse_backend(const std::string& name);

}  // namespace viewer
