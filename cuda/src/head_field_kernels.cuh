#pragma once
/// @file head_field_kernels.cuh
/// The kernels of the device head field (MotionParams::pressure): the solver of
/// granular/step/head_field.hpp over the device grid, as the CPU backend runs it
/// (cpu_head_field.cpp), and the wake of the bricks where a pressure move may start. Each kernel
/// calls the shared constexpr code per coarse cell or per line, so the heads and the woken bricks
/// are the CPU's bit for bit: a seed depends only on the cells, a sweep pass carries the head along
/// each line in the line's own sequential order (the lines of one pass share no coarse cell), and
/// the passes run in the CPU's order, one launch each.

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>

#include "cuda_check.cuh"
#include "granular/bricks.hpp"
#include "granular/geometry.hpp"
#include "sparse_kernel.cuh"
#include "step/brick_grid.hpp"
#include "step/head_field.hpp"
#include "step/step_materials.hpp"

namespace granular::cuda {

/// Threads per CUDA block of the head field's kernels.
inline constexpr int kHeadThreads = 256;

/// A cell byte of the device grid as head::seed and head::may_press read it (inside the grid only).
struct HeadCells {
  const std::uint8_t* cells;  ///< the grid's bytes (x fastest)
  Int3 size;                  ///< the grid's extent

  /// The byte of cell (x, y, z).
  constexpr std::uint8_t operator()(int x, int y, int z) const {
    return cells[std::size_t(x) + std::size_t(size.x) * (std::size_t(y) + std::size_t(size.y) * std::size_t(z))];
  }
};

/// Coarse cells of a coarse grid of `c`.
__host__ __device__ inline std::uint64_t coarse_count(Int3 c) {
  return std::uint64_t(c.x) * std::uint64_t(c.y) * std::uint64_t(c.z);
}

/// The seed and links of every coarse cell (head::seed), one coarse cell per thread.
static __global__ void head_seed_kernel(HeadCells at, StepMaterials m, Int3 c, std::int32_t* heads, std::uint8_t* links) {
  const std::uint64_t total = coarse_count(c);
  for (std::uint64_t n = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; n < total;
       n += std::uint64_t(gridDim.x) * blockDim.x) {
    const int i = int(n % std::uint64_t(c.x)), j = int(n / std::uint64_t(c.x) % std::uint64_t(c.y)),
              k = int(n / (std::uint64_t(c.x) * std::uint64_t(c.y)));
    std::uint8_t l = 0;
    heads[n] = head::seed(at, at.size, m, i, j, k, l);
    links[n] = l;
  }
}

/// One sweep pass along `axis` (0: x, 1: y, 2: z), forward or backward (head::sweep_line), one line
/// per thread: line (p, q) starts at the coarse cell whose coordinate along the axis is 0 and whose
/// other two are (p, q) in the CPU's order (x: (j, k), y: (i, k), z: (i, j)).
static __global__ void head_sweep_kernel(std::int32_t* heads, const std::uint8_t* links, Int3 c, int axis, bool forward,
                                         bool dry) {
  const int u = axis == 0 ? c.y : c.x, v = axis == 2 ? c.y : c.z;
  const std::int64_t stride = axis == 0 ? 1 : axis == 1 ? std::int64_t(c.x) : std::int64_t(c.x) * c.y;
  const int count = axis == 0 ? c.x : axis == 1 ? c.y : c.z;
  const std::uint8_t link = axis == 0 ? head::kLinkX : axis == 1 ? head::kLinkY : head::kLinkZ;
  const std::uint64_t lines = std::uint64_t(u) * std::uint64_t(v);
  for (std::uint64_t line = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; line < lines;
       line += std::uint64_t(gridDim.x) * blockDim.x) {
    const int p = int(line % std::uint64_t(u)), q = int(line / std::uint64_t(u));
    const std::int64_t first = axis == 0   ? head::coarse_index(c, 0, p, q)
                               : axis == 1 ? head::coarse_index(c, p, 0, q)
                                           : head::coarse_index(c, p, q, 0);
    head::sweep_line(heads, links, first, stride, count, link, forward, dry);
  }
}

/// Flags in `pressing` (one byte per brick of a grid of `bricks` bricks per axis) the brick of every
/// coarse cell where a pressure move may start (head::may_press), as CpuHeadField::solve lists them.
static __global__ void head_pressing_kernel(HeadCells at, StepMaterials m, Int3 c, const std::int32_t* heads,
                                            Int3 bricks, std::uint8_t* pressing) {
  const std::uint64_t total = coarse_count(c);
  for (std::uint64_t n = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; n < total;
       n += std::uint64_t(gridDim.x) * blockDim.x) {
    const std::int32_t h = heads[n];
    if (h <= head::kSunk) continue;
    const int i = int(n % std::uint64_t(c.x)), j = int(n / std::uint64_t(c.x) % std::uint64_t(c.y)),
              k = int(n / (std::uint64_t(c.x) * std::uint64_t(c.y)));
    if (!head::may_press(at, at.size, m, i, j, k, h)) continue;
    const std::uint32_t b = brick_index(bricks, 2 * i / kBrickSize, 2 * j / kBrickSize, 2 * k / kBrickSize);
    if (pressing[b] == 0) pressing[b] = 1;  // every writer stores the same byte
  }
}

/// CUDA blocks for a head field kernel over `n` items (coarse cells, lines or bricks).
inline unsigned head_blocks(std::uint64_t n) {
  const std::uint64_t blocks = (n + kHeadThreads - 1) / kHeadThreads;
  return unsigned(blocks < 65536 ? (blocks > 0 ? blocks : 1) : 65536);
}

/// Enqueues the solve of the heads of the grid `at` into `heads` and `links` (one per coarse cell):
/// the seeds, then the passes of head::sweep_pass in order.
static inline void launch_head_solve(HeadCells at, const StepMaterials& m, std::int32_t* heads, std::uint8_t* links,
                                     cudaStream_t stream) {
  const Int3 c = head::coarse_size(at.size);
  head_seed_kernel<<<head_blocks(coarse_count(c)), kHeadThreads, 0, stream>>>(at, m, c, heads, links);
  check_launch("head seed kernel launch");
  const std::uint64_t lines[3] = {std::uint64_t(c.y) * std::uint64_t(c.z), std::uint64_t(c.x) * std::uint64_t(c.z),
                                  std::uint64_t(c.x) * std::uint64_t(c.y)};
  for (int n = 0; n < head::kPassCount; ++n) {
    const head::SweepPass pass = head::sweep_pass(n);
    head_sweep_kernel<<<head_blocks(lines[pass.axis]), kHeadThreads, 0, stream>>>(heads, links, c, pass.axis,
                                                                                  pass.forward, pass.dry);
    check_launch("head sweep kernel launch");
  }
}

/// Enqueues the wake of the bricks holding a coarse cell of `heads` where a pressure move may start
/// (dirty, their neighbourhoods awake, the awake list rebuilt), `pressing` being one zeroed byte per
/// brick that the wake leaves zeroed.
static inline void launch_pressing_wake(HeadCells at, const StepMaterials& m, const std::int32_t* heads,
                                        std::uint8_t* pressing, const SparseParams& s, cudaStream_t stream) {
  const Int3 c = head::coarse_size(at.size);
  head_pressing_kernel<<<head_blocks(coarse_count(c)), kHeadThreads, 0, stream>>>(at, m, c, heads, s.bricks, pressing);
  check_launch("head pressing kernel launch");
  launch_wake_flagged(s, pressing, stream);
}

}  // namespace granular::cuda
