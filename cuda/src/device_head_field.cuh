#pragma once
/// @file device_head_field.cuh
/// The CUDA backend's head field (MotionParams::pressure): the device counterpart of CpuHeadField
/// (cpu_head_field.hpp). Its buffers live beside the cells; each tick's solve and wake are enqueued
/// on the backend's stream (head_field_kernels.cuh), with no host synchronisation.

#include <cuda_runtime.h>

#include <cstdint>

#include "cuda_check.cuh"
#include "device_buffer.cuh"
#include "granular/geometry.hpp"
#include "head_field_kernels.cuh"
#include "sparse_kernel.cuh"
#include "step/head_field.hpp"
#include "step/step_materials.hpp"

namespace granular::cuda {

/// The head field of a grid on the device and the bricks where it lets a liquid move.
class DeviceHeadField {
 public:
  /// The field of a grid of `size` cells (a head and a link byte per coarse cell) and, for sparse
  /// stepping (`bricks` > 0), a byte per brick for the wake, zeroed on `stream`.
  DeviceHeadField(Int3 size, std::uint32_t bricks, cudaStream_t stream)
      : size_(size),
        heads_(coarse_count(head::coarse_size(size)), "the head field"),
        links_(heads_.size(), "the head field's links"),
        pressing_(bricks, "the bricks a head presses in") {
    if (bricks > 0)
      check(cudaMemsetAsync(pressing_.data(), 0, pressing_.bytes(), stream), "cudaMemsetAsync (pressing bricks)");
  }

  /// The heads, one per coarse cell (head::coarse_index), in device memory.
  const std::int32_t* heads() const { return heads_.data(); }

  /// Enqueues on `stream` the solve of the heads from `cells` (the grid's bytes) and, with `sparse`
  /// (not null), the wake of the bricks that hold a coarse cell where a pressure move may start
  /// (head::may_press): what CpuBackend::step does before each tick's sub-steps.
  void enqueue(const std::uint8_t* cells, const StepMaterials& materials, const SparseParams* sparse,
               cudaStream_t stream) {
    const HeadCells at{cells, size_};
    launch_head_solve(at, materials, heads_.data(), links_.data(), stream);
    if (sparse != nullptr) launch_pressing_wake(at, materials, heads_.data(), pressing_.data(), *sparse, stream);
  }

 private:
  Int3 size_;
  DeviceBuffer<std::int32_t> heads_;
  DeviceBuffer<std::uint8_t> links_;
  DeviceBuffer<std::uint8_t> pressing_;  // per brick: a coarse cell in it may start a pressure move
};

}  // namespace granular::cuda
