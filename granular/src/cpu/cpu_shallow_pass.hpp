#pragma once
/// @file cpu_shallow_pass.hpp
/// The CPU backend's pass of MotionParams::shallow (granular/step/shallow_water.hpp): the face plane
/// and the pass's scratch, and one tick's pass over rows of columns spread over the backend's task
/// system.

#include <cstdint>
#include <span>
#include <vector>

#include "granular/geometry.hpp"
#include "granular/task_system.hpp"
#include "step/shallow_water.hpp"
#include "step/step_materials.hpp"

namespace granular {

/// The face plane of a grid and the pass that moves its liquid as shallow water.
class CpuShallowPass {
 public:
  /// The plane of a grid of `size`, every face at rest.
  explicit CpuShallowPass(Int3 size);

  /// Runs one tick's pass over `cells` (the grid of the constructor's size, x fastest). Returns
  /// the bricks whose cells it changed (bricks.hpp indices), ascending and each once.
  std::vector<std::uint32_t> run(std::uint8_t* cells, const StepMaterials& materials, TaskSystem& tasks);

  /// True when the last run changed nothing (no cell, no face): run again on the same cells, the
  /// pass would change nothing either.
  bool at_rest() const { return at_rest_; }

  /// The face plane: the x faces' velocities, the y faces', the x faces' fractions, the y faces'
  /// (nx ny int32 each, x fastest), or empty when every face is 0.
  std::vector<std::int32_t> faces() const;

  /// Replaces the face plane with `faces` (as faces() gives it; empty: every face 0).
  void set_faces(std::span<const std::int32_t> faces);

  /// The face plane's int32 count: 4 per column.
  std::size_t face_count() const { return 4 * columns_; }

 private:
  Int3 size_;
  std::size_t columns_;
  std::vector<shallow::Column> column_;
  std::vector<std::int64_t> surface_, limit_;
  std::vector<std::int32_t> faces_;  ///< the face plane (shallow::PlaneBuffers::faces)
  std::vector<std::int32_t> next_u_, cells_;
  std::vector<std::int64_t> volume_;
  std::vector<std::int32_t> changed_lo_, changed_hi_;  ///< per column: the cells a move changed this run
  bool at_rest_ = false;

  shallow::Plane plane();
};

}  // namespace granular
