#pragma once
/// @file cpu_head_field.hpp
/// The CPU backend's head field (MotionParams::pressure): the solver of granular/step/head_field.hpp
/// over the host grid, its lines spread over the backend's task system.

#include <cstdint>
#include <vector>

#include "granular/task_system.hpp"
#include "granular/geometry.hpp"
#include "step/step_materials.hpp"

namespace granular {

/// The head field of a grid and where it lets a liquid move (MotionParams::pressure).
class CpuHeadField {
 public:
  /// The field of a grid of `size` cells (one head and one link byte per coarse cell).
  explicit CpuHeadField(Int3 size);
  /// Computes the heads from `cells` (the seeds, then the passes of head::sweep_pass) and returns
  /// the bricks (bricks.hpp) that hold a coarse cell where a pressure move may start
  /// (head::may_press), ascending and each once.
  std::vector<std::uint32_t> solve(const std::uint8_t* cells, const StepMaterials& materials, TaskSystem& tasks);
  /// The heads, one per coarse cell (head::coarse_index).
  const std::int32_t* heads() const { return heads_.data(); }

 private:
  Int3 size_, coarse_;
  std::vector<std::int32_t> heads_;
  std::vector<std::uint8_t> links_;
  std::vector<std::uint8_t> pressing_;  // per brick: a coarse cell in it may start a pressure move
};

}  // namespace granular
