#pragma once
/// @file device_shallow_pass.cuh
/// The CUDA backend's face plane and shallow-water pass (MotionParams::shallow): the device
/// counterpart of CpuShallowPass (cpu_shallow_pass.hpp). Its buffers live beside the cells; each
/// tick's pass is enqueued on the backend's stream (shallow_kernels.cuh) with no host
/// synchronisation, and whether it changed anything stays on the device until asked. As on the CPU,
/// the tick's iterations end at the first that changed nothing: the kernels after it return at once.

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cuda_check.cuh"
#include "device_buffer.cuh"
#include "granular/errors.hpp"
#include "granular/geometry.hpp"
#include "shallow_kernels.cuh"
#include "sparse_kernel.cuh"
#include "step/shallow_water.hpp"
#include "step/step_materials.hpp"

namespace granular::cuda {

/// The face plane of a grid on the device and the pass that moves its liquid.
class DeviceShallowPass {
 public:
  /// The plane of a grid of `size` (every face at rest) and the pass's scratch, and for sparse
  /// stepping (`bricks` > 0) a byte per brick for the wake; zeroed on `stream`.
  DeviceShallowPass(Int3 size, std::uint32_t bricks, cudaStream_t stream)
      : size_(size),
        columns_(std::size_t(size.x) * std::size_t(size.y)),
        column_(columns_, "the shallow-water pass's columns"),
        surface_(columns_, "the shallow-water pass's surfaces"),
        limit_(2 * columns_, "the shallow-water pass's outflow limits"),
        faces_(4 * columns_, "the face plane"),
        next_u_(2 * columns_, "the shallow-water pass's next velocities"),
        cells_(2 * columns_, "the shallow-water pass's whole cells"),
        volume_(2 * columns_, "the shallow-water pass's volumes"),
        lo_(columns_, "the shallow-water pass's changed cells"),
        hi_(columns_, "the shallow-water pass's changed cells"),
        flags_(1, "the shallow-water pass's flags"),
        bricks_(bricks, "the bricks the shallow-water pass changed") {
    check(cudaMemsetAsync(faces_.data(), 0, faces_.bytes(), stream), "cudaMemsetAsync (face plane)");
    check(cudaMemsetAsync(cells_.data(), 0, cells_.bytes(), stream), "cudaMemsetAsync (shallow cells)");
    const std::vector<std::int32_t> lo(columns_, size.z);
    check(cudaMemcpyAsync(lo_.data(), lo.data(), lo_.bytes(), cudaMemcpyHostToDevice, stream), "cudaMemcpyAsync (shallow lo)");
    check(cudaMemsetAsync(hi_.data(), 0xFF, hi_.bytes(), stream), "cudaMemsetAsync (shallow hi)");  // -1
    mark_not_at_rest(stream);
    if (bricks > 0) check(cudaMemsetAsync(bricks_.data(), 0, bricks_.bytes(), stream), "cudaMemsetAsync (shallow bricks)");
  }

  /// Enqueues on `stream` one tick's pass over `cells` and, with `sparse` (not null), the wake of
  /// the bricks it changed: what CpuBackend::run_shallow_pass does after a tick.
  void enqueue(std::uint8_t* cells, const StepMaterials& m, const SparseParams* sparse, cudaStream_t stream) {
    const shallow::Plane p = plane();
    const unsigned blocks = shallow_blocks(columns_);
    check(cudaMemsetAsync(flags_.data(), 0, flags_.bytes(), stream), "cudaMemsetAsync (shallow flags)");
    shallow_scan_kernel<<<blocks, kShallowThreads, 0, stream>>>(cells, size_, m, p);
    check_launch("shallow-water scan kernel launch");
    shallow_settle_kernel<<<blocks, kShallowThreads, 0, stream>>>(p, flags_.data());
    check_launch("shallow-water settle kernel launch");
    const DeviceShallowGrid grid{cells, columns_, lo_.data(), hi_.data()};
    for (int i = 0; i < shallow::kIterations; ++i) {
      for (int step = 0; step < 4; ++step) {
        shallow_step_kernel<<<blocks, kShallowThreads, 0, stream>>>(p, step, flags_.data());
        check_launch("shallow-water step kernel launch");
      }
      for (int phase = 0; phase < 4; ++phase) {
        shallow_move_kernel<<<shallow_blocks(columns_ / 2 + std::size_t(size_.x) + std::size_t(size_.y)), kShallowThreads,
                              0, stream>>>(p, grid, m, phase, flags_.data());
        check_launch("shallow-water move kernel launch");
      }
      shallow_iteration_end_kernel<<<blocks, kShallowThreads, 0, stream>>>(p, flags_.data());
      check_launch("shallow-water iteration end kernel launch");
    }
    const SparseParams s = sparse != nullptr ? *sparse : SparseParams{};
    shallow_changed_kernel<<<blocks, kShallowThreads, 0, stream>>>(size_, grid, sparse != nullptr, s, bricks_.data());
    check_launch("shallow-water changed kernel launch");
    if (sparse != nullptr) launch_wake_flagged(s, bricks_.data(), stream);
  }

  /// True when the last pass changed nothing (no cell, no face). Waits for `stream`.
  bool at_rest(cudaStream_t stream) const {
    ShallowFlags flags{};
    check(cudaMemcpyAsync(&flags, flags_.data(), sizeof flags, cudaMemcpyDeviceToHost, stream),
          "cudaMemcpyAsync (shallow flags)");
    check(cudaStreamSynchronize(stream), "cudaStreamSynchronize (shallow flags)");
    return flags.pass == 0;
  }

  /// The face plane copied to the host (shallow_water.hpp's order), or empty when every face is 0.
  /// Waits for `stream`.
  std::vector<std::int32_t> read(cudaStream_t stream) const {
    std::vector<std::int32_t> faces(4 * columns_);
    check(cudaMemcpyAsync(faces.data(), faces_.data(), faces_.bytes(), cudaMemcpyDeviceToHost, stream),
          "cudaMemcpyAsync (face plane to the host)");
    check(cudaStreamSynchronize(stream), "cudaStreamSynchronize (face plane)");
    if (std::all_of(faces.begin(), faces.end(), [](std::int32_t f) { return f == 0; })) return {};
    return faces;
  }

  /// Replaces the face plane with `faces` (empty: all zero) and marks the pass as not at rest;
  /// returns once the device holds it.
  void write(std::span<const std::int32_t> faces, cudaStream_t stream) {
    if (faces.empty())
      check(cudaMemsetAsync(faces_.data(), 0, faces_.bytes(), stream), "cudaMemsetAsync (face plane)");
    else
      check(cudaMemcpyAsync(faces_.data(), faces.data(), faces_.bytes(), cudaMemcpyHostToDevice, stream),
            "cudaMemcpyAsync (face plane to the device)");
    mark_not_at_rest(stream);
    check(cudaStreamSynchronize(stream), "cudaStreamSynchronize (face plane)");
  }

  /// Enqueues flags that say the last pass changed something (a new or rewritten plane).
  void mark_not_at_rest(cudaStream_t stream) {
    check(cudaMemsetAsync(flags_.data(), 0, flags_.bytes(), stream), "cudaMemsetAsync (shallow flags)");
    check(cudaMemsetAsync(&flags_.data()->pass, 0x01, 1, stream), "cudaMemsetAsync (shallow flags)");
  }

  /// The face plane's int32 count: 4 per column.
  std::size_t face_count() const { return 4 * columns_; }

 private:
  shallow::Plane plane() {
    return shallow::plane_over(size_, shallow::PlaneBuffers{column_.data(), surface_.data(), limit_.data(), faces_.data(),
                                                            next_u_.data(), volume_.data(), cells_.data()});
  }

  Int3 size_;
  std::size_t columns_;
  DeviceBuffer<shallow::Column> column_;
  DeviceBuffer<std::int64_t> surface_, limit_;
  DeviceBuffer<std::int32_t> faces_;  // the face plane: u x, u y, fraction x, fraction y
  DeviceBuffer<std::int32_t> next_u_, cells_;
  DeviceBuffer<std::int64_t> volume_;
  DeviceBuffer<std::int32_t> lo_, hi_;
  DeviceBuffer<ShallowFlags> flags_;
  DeviceBuffer<std::uint8_t> bricks_;
};

}  // namespace granular::cuda
