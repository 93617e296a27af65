#include "world/world_def_validation.hpp"

#include <string>
#include <tuple>
#include <utility>

#include "granular/errors.hpp"
#include "granular/extend/threads.hpp"
#include "granular/grid.hpp"
#include "granular/task_system.hpp"
#include "util/number_text.hpp"

namespace granular {

int validate_world_def(const WorldDef& def, Int3 size) {
  int threads = resolve_threads(def.threads, "WorldDef::threads");
  if (def.task_system) {
    threads = def.task_system->thread_count();
    if (threads < 1 || threads > max_threads())
      throw InvalidArgument("WorldDef::task_system->thread_count() = " + std::to_string(threads) + "; use 1.." +
                            std::to_string(max_threads()) + " (4 times the hardware threads)");
  }
  if (def.backend != BackendKind::Auto && def.backend != BackendKind::Cpu && def.backend != BackendKind::Cuda)
    throw InvalidArgument("WorldDef::backend = " + std::to_string(int(def.backend)) +
                          " is not a BackendKind; use Auto, Cpu or Cuda");
  for (const auto& [field, value] : {std::pair{"dense_fraction", def.cuda.dense_fraction},
                                     std::pair{"motion_dense_fraction", def.cuda.motion_dense_fraction}})
    if (!(value >= 0.0 && value <= 1.0))
      throw InvalidArgument(std::string("WorldDef::cuda.") + field + " = " + std::to_string(value) +
                            "; use a fraction of the bricks in 0..1 (0: always dense-recording, 1: never)");
  if (!(def.cell_metres > 0 && def.cell_metres <= 1e3))
    throw InvalidArgument("WorldDef::cell_metres = " + number_text(def.cell_metres) +
                          "; a cell's edge is a length in metres above 0 and at most 1000");
  if (!is_valid_material_value(to_cell(def.body_material)))
    throw InvalidArgument("WorldDef::body_material = " + std::to_string(unsigned(to_cell(def.body_material))) +
                          " is not a state (0..7)");
  for (const auto& [axis, origin, extent] : {std::tuple{"x", def.domain_origin.x, size.x},
                                            std::tuple{"y", def.domain_origin.y, size.y},
                                            std::tuple{"z", def.domain_origin.z, size.z}})
    if (origin < 0 || origin % 2 != 0 || origin > kMaxGridExtent - extent)
      throw InvalidArgument(std::string("WorldDef::domain_origin.") + axis + " = " + std::to_string(origin) +
                            "; use an even coordinate in 0.." + std::to_string(kMaxGridExtent - extent) +
                            " (the grid must lie inside a " + std::to_string(kMaxGridExtent) +
                            "-cell world, on the block partition's parity)");
  return threads;
}

}  // namespace granular
