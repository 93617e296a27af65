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

/// Closes the trains of the columns of `cells` (a grid of `size`, x fastest). With `active` (the
/// awake bricks, bricks.hpp indices) only the columns of a brick column holding one of them are
/// walked, each over the grid's whole height: a train's grains are moving, so their bricks are awake.
/// Returns the bricks whose cells changed, ascending and each once.
std::vector<std::uint32_t> close_trains(std::uint8_t* cells, Int3 size, const StepMaterials& materials,
                                        const std::vector<std::uint32_t>* active, TaskSystem& tasks);

}  // namespace granular
