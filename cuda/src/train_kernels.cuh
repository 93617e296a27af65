#pragma once
/// @file train_kernels.cuh
/// The kernels of MotionParams::trains: every column's trains closed after the last sub-step of a
/// tick (granular/step/column_trains.hpp), as the CPU backend does it (cpu_column_trains.cpp), and
/// the wake of the bricks they changed. A column is one thread's, walked bottom up by the shared
/// TrainWalk, and no two columns share a cell, so the cells are the CPU's bit for bit.

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>

#include "cuda_check.cuh"
#include "granular/geometry.hpp"
#include "sparse_kernel.cuh"
#include "step/brick_grid.hpp"
#include "step/column_trains.hpp"
#include "step/step_materials.hpp"

namespace granular::cuda {

/// Threads per CUDA block of the train kernel.
inline constexpr int kTrainThreads = 256;

/// One column of the device grid, as TrainWalk reads it. With sparse stepping each brick of its brick
/// column where it changed a cell is flagged in the sparse state's `changed`, and in `flags` (to wake)
/// where the block step sees the change.
struct DeviceColumn {
  std::uint8_t* first;  ///< the column's cell at z = 0
  std::size_t layer;    ///< cells per layer
  bool sparse;          ///< flag the changed bricks
  const SparseParams* s;  ///< the sparse state (sparse)
  std::uint8_t* flags;  ///< a byte per brick: wake it (sparse)
  int bx, by;           ///< the column's brick column
  constexpr std::uint8_t get(int z) const { return first[std::size_t(z) * layer]; }
  constexpr void set(int z, std::uint8_t byte) const { first[std::size_t(z) * layer] = byte; }
  constexpr void changed(int z, bool seen) const {
    if (!sparse) return;
    const std::uint32_t b = brick_index(s->bricks, bx, by, brick_of(z));
    if (seen && flags[b] == 0) flags[b] = 1;  // every writer stores the same byte
    if (s->changed[b] == 0) s->changed[b] = 1;
  }
};

/// Closes the trains of every column (one per thread), in a rule set whose highest motion level is
/// `max_level`. With `sparse` only the columns of a brick column holding an awake brick are walked,
/// and each brick a train changed is flagged in the sparse state's `changed`, and in `flags` (one
/// byte per brick) where the block step sees the change.
static __global__ void close_trains_kernel(std::uint8_t* cells, Int3 size, StepMaterials m, int max_level, bool sparse,
                                           SparseParams s, std::uint8_t* flags) {
  const std::uint64_t columns = std::uint64_t(size.x) * std::uint64_t(size.y);
  const std::size_t layer = std::size_t(columns);
  for (std::uint64_t n = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; n < columns;
       n += std::uint64_t(gridDim.x) * blockDim.x) {
    const int x = int(n % std::uint64_t(size.x)), y = int(n / std::uint64_t(size.x));
    const int bx = brick_of(x), by = brick_of(y);
    if (sparse) {
      bool awake = false;
      for (int bz = 0; bz < s.bricks.z && !awake; ++bz) awake = s.awake[brick_index(s.bricks, bx, by, bz)] != 0;
      if (!awake) continue;
    }
    DeviceColumn column{cells + n, layer, sparse, &s, flags, bx, by};
    trains::close_column(column, 0, size.z, m, max_level);
  }
}

/// Enqueues the closing of the trains of the grid `cells` of `size`, in a rule set whose highest motion
/// level is `max_level`; with `sparse` (not null) only the columns of awake brick columns, and the
/// bricks where the block step sees a change wake as a tool's write wakes them (dirty, their
/// neighbourhoods awake, the awake list rebuilt), `flags` being one zeroed byte per brick that the
/// wake leaves zeroed.
static inline void launch_close_trains(std::uint8_t* cells, Int3 size, const StepMaterials& m, int max_level,
                                       const SparseParams* sparse, std::uint8_t* flags, cudaStream_t stream) {
  const std::uint64_t columns = std::uint64_t(size.x) * std::uint64_t(size.y);
  const std::uint64_t blocks = (columns + kTrainThreads - 1) / kTrainThreads;
  const SparseParams s = sparse != nullptr ? *sparse : SparseParams{};
  close_trains_kernel<<<unsigned(blocks < 65536 ? blocks : 65536), kTrainThreads, 0, stream>>>(
      cells, size, m, max_level, sparse != nullptr, s, flags);
  check_launch("close trains kernel launch");
  if (sparse != nullptr) launch_wake_flagged(s, flags, stream);
}

}  // namespace granular::cuda
