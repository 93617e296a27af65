#pragma once
/// @file world_def.hpp
/// Everything needed to create a World, with defaults (Box2D's b2DefaultWorldDef, as a struct).

#include <cstdint>
#include <memory>
#include <string>

#include "granular/extend/backend_factory.hpp"
#include "granular/cuda_options.hpp"
#include "granular/geometry.hpp"
#include "granular/rule_set.hpp"
#include "granular/task_system.hpp"

namespace granular {

/// Which compute backend steps the world.
enum class BackendKind {
  Auto,  ///< the CUDA backend when the program links it (granular::granular of a CUDA build) and a
         ///< usable GPU exists, otherwise the CPU (with a one-line notice)
  Cpu,   ///< the multithreaded CPU reference
  Cuda,  ///< the CUDA backend (throws BackendError when it is not linked or no GPU is usable)
};

/// Parameters of a World. Every field has a usable default.
struct WorldDef {
  Int3 size{64, 64, 64};        ///< grid extent in cells (z is up)
  std::string rules = "inertial-24-flow";  ///< rule-set preset name (see rule_presets.hpp);
                                          ///< "inertial-24-flow" measures best on the accuracy
                                          ///< suite and runs in real time on a GPU up to 1024^3
                                          ///< (docs/ACCURACY.md), "paper" is the paper's
  std::shared_ptr<const RuleSet> rule_set;  ///< a rule set of the game's own (e.g. a copy of
                                            ///< granular::preset(...) with a changed material table);
                                            ///< when set it wins over `rules`
  std::uint64_t seed = 0;       ///< seed of every random choice the rules make; same seed, same result
  BackendKind backend = BackendKind::Auto;  ///< compute backend
  BackendFactory backend_factory;  ///< when set, creates the backend instead (wins over `backend`):
                                   ///< a backend of the game's own, or one chosen its own way
  int threads = 0;              ///< threads of the CPU backend's own pool (and of the pool a world on
                                ///< another backend starts for its bodies' stamps, at its first tick
                                ///< with bodies); 0 = all hardware threads, at most max_threads()
                                ///< (threads.hpp); with a task_system, its thread_count() counts instead
  std::shared_ptr<TaskSystem> task_system;  ///< the game's threads (task_system.hpp): when set, the
                                            ///< CPU backend runs every parallel loop of a step on it,
                                            ///< and the bodies' stamps too, and starts no threads for stepping (creating the world
                                            ///< still builds its tables on short-lived threads, up to
                                            ///< thread_count() of them); null = its own pool of `threads`
  bool use_lut_cache = true;    ///< load/save the transition table from/to the on-disk cache
  std::string lut_cache_dir;    ///< cache folder; empty = $GRANULAR_CACHE_DIR, else $XDG_CACHE_HOME/granular, else ~/.cache/granular
  bool sparse = true;           ///< step only bricks where something may move (same result as dense;
                                ///< false steps every block every tick, for comparison)
  CudaOptions cuda;             ///< settings only the CUDA backend reads (cuda_options.hpp)
  double cell_metres = 0.005;   ///< the edge of a cell in metres: the scale of the forces bodies feel
                                ///< (body.hpp) with ticks of tick_seconds(rules, cell_metres); > 0
  Material body_material = Material::State7;  ///< the state a body's cells hold in the grid (body.hpp):
                                              ///< a static material of the rule set, which no tool or rule
                                              ///< uses for anything else
  Int3 domain_origin{};         ///< where this world's cell (0, 0, 0) lies when it is one part of a
                                ///< larger world (a DistributedWorld's slab, distributed_world.hpp):
                                ///< the rules' random draws and pour's choice of cells then are the
                                ///< whole world's at the same place. Each coordinate even (the block
                                ///< partition's parity) and 0 or more; (0, 0, 0) for a world of its own
};

/// The default WorldDef (identical to a value-initialised one; provided for symmetry with Box2D).
inline WorldDef default_world_def() { return WorldDef{}; }

/// "auto", "cpu" or "cuda".
const char* backend_name(BackendKind kind) noexcept;

}  // namespace granular
