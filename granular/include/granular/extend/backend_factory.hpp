#pragma once
/// @file extend/backend_factory.hpp
/// How a backend is created: everything a World hands a backend at creation in one struct, and the
/// factory type that turns it into a Backend (the CPU one here; the CUDA one registers itself,
/// backend_registry.hpp; a game may pass its own as WorldDef::backend_factory).

#include <cstdint>
#include <functional>
#include <memory>

#include "granular/cuda_options.hpp"
#include "granular/geometry.hpp"

namespace granular {

class Backend;
class Grid;
class Lut;
class TaskSystem;
struct RuleSet;

/// What a backend is created from. World fills every field; a factory reads those it needs.
struct BackendCreateInfo {
  const Grid& initial;                   ///< the cells the backend starts from (it keeps a copy)
  std::shared_ptr<const Lut> lut;        ///< the transition table of `rules` (never null)
  std::shared_ptr<const RuleSet> rules;  ///< the rule set: random flags and motion model (never null)
  std::uint64_t seed = 0;                ///< WorldDef::seed
  bool sparse = true;                    ///< WorldDef::sparse: step only the awake bricks
  int threads = 1;                       ///< CPU threads for the backend's own pool, 1..max_threads()
                                         ///< (threads.hpp): WorldDef::threads resolved, or
                                         ///< task_system->thread_count() when that is set
  std::shared_ptr<TaskSystem> task_system;  ///< WorldDef::task_system: the game's threads for every
                                            ///< parallel loop of a CPU step; null = a pool of `threads`
  CudaOptions cuda;                      ///< WorldDef::cuda
  Int3 domain_origin{};                  ///< WorldDef::domain_origin: where the grid's cell (0, 0, 0) lies in
                                         ///< the whole world, which every random draw of the step must use
                                         ///< (block_random_keyed's origin); a backend that cannot must
                                         ///< throw BackendError when it is not (0, 0, 0)
};

/// Creates a backend holding a copy of info.initial. Throws BackendError when the backend cannot
/// run here, OutOfMemory when the grid does not fit, InvalidArgument for a bad field.
using BackendFactory = std::function<std::unique_ptr<Backend>(const BackendCreateInfo& info)>;

/// The multithreaded CPU backend, always present in the core library: steps on info.task_system
/// when set, else on a pool of info.threads threads it starts. Throws InvalidArgument for an empty
/// grid, a null table or rule set, or threads outside 1..max_threads(); BackendError when the system
/// refuses to start a thread.
std::unique_ptr<Backend> make_cpu_backend(const BackendCreateInfo& info);

}  // namespace granular
