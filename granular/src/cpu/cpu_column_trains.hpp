#pragma once
/// @file cpu_column_trains.hpp
/// The CPU backend's pass of MotionParams::trains: every column's trains closed
/// (granular/step/column_trains.hpp) after the last sub-step of a tick, rows of columns spread over
/// the backend's task system.

#include <cstdint>
#include <vector>

#include "granular/geometry.hpp"
#include "granular/task_system.hpp"
#include "step/step_materials.hpp"

namespace granular {

/// The bricks a trains pass changed, ascending and each once.
struct TrainChanges {
  std::vector<std::uint32_t> seen;     ///< bricks with a change the block step sees: they wake
  std::vector<std::uint32_t> changed;  ///< bricks with any changed cell (inside a carried train too)
};

/// Closes the trains of the columns of `cells` (a grid of `size`, x fastest), in a rule set whose
/// highest motion level is `max_level`. With `active` (the awake bricks, bricks.hpp indices) only the
/// columns of a brick column holding one of them are walked, each over the grid's whole height: a
/// train's grains are moving, and a carried train's sweep keeps its bricks awake (carried_cells.hpp).
TrainChanges close_trains(std::uint8_t* cells, Int3 size, const StepMaterials& materials, int max_level,
                          const std::vector<std::uint32_t>* active, TaskSystem& tasks);

}  // namespace granular
