#pragma once
/// @file world_def.hpp
/// Everything needed to create a World, with defaults (Box2D's b2DefaultWorldDef, as a struct).

#include <cstdint>
#include <string>

#include "granular/geometry.hpp"

namespace granular {

/// Which compute backend steps the world.
enum class BackendKind {
  Auto,  ///< the CUDA backend when a usable GPU exists, otherwise the CPU (with a one-line notice)
  Cpu,   ///< the multithreaded CPU reference
  Cuda,  ///< the CUDA backend (throws BackendError when unavailable)
};

/// Parameters of a World. Every field has a usable default.
struct WorldDef {
  Int3 size{64, 64, 64};        ///< grid extent in cells (z is up)
  std::string rules = "inertial-24";  ///< rule-set preset name (see rule_presets.hpp); "inertial-24"
                                     ///< measures best on the accuracy suite and runs in real time on a
                                     ///< GPU up to 1024^3 (docs/ACCURACY.md), "paper" is the paper's
  std::uint64_t seed = 0;       ///< seed of every random choice the rules make; same seed, same result
  BackendKind backend = BackendKind::Auto;  ///< compute backend
  int threads = 0;              ///< CPU worker threads; 0 = all hardware threads
  bool use_lut_cache = true;    ///< load/save the transition table from/to the on-disk cache
  std::string lut_cache_dir;    ///< cache folder; empty = $GRANULAR_CACHE_DIR, else $XDG_CACHE_HOME/granular, else ~/.cache/granular
  bool sparse = true;           ///< step only bricks where something may move (same result as dense;
                                ///< false steps every block every tick, for comparison)
  double dense_fraction = 0.125;  ///< CUDA sparse stepping: when more than this fraction of the bricks
                                  ///< was awake at the last tick the host knows of, step() runs the dense
                                  ///< kernels, recording the sparse state (same cells and activity
                                  ///< figures, faster when much is awake); 0 always, 1 never; 0..1
};

/// The default WorldDef (identical to a value-initialised one; provided for symmetry with Box2D).
inline WorldDef default_world_def() { return WorldDef{}; }

/// "auto", "cpu" or "cuda".
const char* backend_name(BackendKind kind) noexcept;

}  // namespace granular
