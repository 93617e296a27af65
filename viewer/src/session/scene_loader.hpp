#pragma once
/// @file scene_loader.hpp
/// Makes the sandbox's World from a scene name (assets/scenes), a grid file or a snapshot, a size
/// and a backend.

#include <memory>
#include <string>
#include <vector>

#include "granular/scene.hpp"
#include "granular/world.hpp"

namespace viewer {

/// What defines the sandbox's world.
struct WorldChoice {
  std::string scene = "bowl";    ///< scene name, scene .json path, .raw/.vox grid file or .gsnap snapshot
  int size = 0;                  ///< scene size parameter N (0: the scene's default)
  std::string backend = "auto";  ///< auto, cpu or cuda
  std::string rules = granular::WorldDef{}.rules;  ///< rule-set preset (the library's default)
  bool rules_given = false;      ///< the user chose `rules` (a snapshot has rules of its own)
  int threads = 0;               ///< CPU threads (0: all)
};

/// A world with its scene's emitters.
struct SandboxWorld {
  std::string scene_name;                  ///< the scene (or grid file, or snapshot) it came from
  int n = 0;                               ///< size parameter used (0 for grid files and snapshots)
  std::vector<granular::Emitter> emitters; ///< the scene's emitters, in cells
  std::unique_ptr<granular::World> world;  ///< the world
};

/// Builds the world; throws granular::Error (InvalidArgument, ParseError, BackendError...) with the
/// library's actionable message on bad input. A snapshot continues under its own rules (chosen
/// rules that differ are an InvalidArgument) and has no emitters; grid files and snapshots are
/// known by their extensions in any case.
SandboxWorld load_world(const WorldChoice& choice);

/// True when `path` names a file load_world takes as a world: a .raw or .vox grid or a .gsnap
/// snapshot (extensions in any case).
bool is_world_file(const std::string& path);

/// Parses "auto", "cpu" or "cuda"; throws granular::InvalidArgument otherwise.
granular::BackendKind parse_backend(const std::string& name);

}  // namespace viewer
