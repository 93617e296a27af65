#pragma once
/// @file step_kernel.cuh
/// One tick of the Margolus partition on the device: one thread per 2x2x2 block. Shared by the
/// CUDA backend and the CUDA benchmark, so both run exactly the same code.
///
/// Identity with the CPU backend (cpu_step.cpp) holds by construction: the offset, block counts,
/// block origins, random draw and symmetry maps come from the same constexpr functions of
/// block.hpp; cells outside the grid read as solid and are never written; the key is looked up in
/// the same result table (derived on the device from the same transition table). With random
/// symmetry the block is viewed in the drawn frame (cell i moves to map[i]), looked up, and moved
/// back (the cell at map[i] returns to i), which is what the CPU's forward and inverse key tables do.

#include <cuda_runtime.h>

#include <cstdint>

#include "cuda_check.cuh"
#include "granular/block.hpp"
#include "granular/geometry.hpp"

namespace granular::cuda {

/// Threads per CUDA block of the step kernel.
inline constexpr int kStepThreads = 256;

/// The state of a cell outside the grid (Material::Solid).
inline constexpr std::uint32_t kOutsideCell = 1;

/// Key of a block whose 8 cells all hold 1 (multiply by a state to get its uniform key).
inline constexpr BlockKey kUniformKeyUnit = 0x249249u;  // octal 11111111

/// Everything one tick of the step kernel reads.
struct StepParams {
  std::uint8_t* cells = nullptr;     ///< the grid on the device, x fastest, one byte per cell
  Int3 size{};                       ///< grid extent
  const BlockKey* result = nullptr;  ///< device result table: per key, the key after its transition
  std::uint64_t seed = 0;            ///< world seed (random symmetry)
  std::uint64_t tick = 0;            ///< the tick computed (selects the offset)
};

/// Linear index offset of block cell i from the block's lowest corner.
__device__ inline std::int64_t block_cell_offset(int i, std::int64_t sy, std::int64_t sz) {
  return std::int64_t(i & 1) + sy * ((i >> 1) & 1) + sz * (i >> 2);
}

/// The tick's blocks; thread (x, y) of CUDA block (bx, by, bz) takes Margolus block
/// (bx * blockDim.x + x, by * blockDim.y + y, bz), so a warp covers consecutive blocks of one row.
template <bool kRandom>
__global__ void __launch_bounds__(kStepThreads) step_kernel(StepParams p) {
  const BlockOffset o = block_offset(p.tick);
  const int bx = int(blockIdx.x * blockDim.x + threadIdx.x);
  const int by = int(blockIdx.y * blockDim.y + threadIdx.y);
  const int bz = int(blockIdx.z);
  if (bx >= block_count(p.size.x, o.x) || by >= block_count(p.size.y, o.y) || bz >= block_count(p.size.z, o.z))
    return;
  const int x0 = 2 * bx - o.x, y0 = 2 * by - o.y, z0 = 2 * bz - o.z;
  const std::int64_t sy = p.size.x, sz = sy * p.size.y;
  const std::int64_t origin = std::int64_t(x0) + sy * y0 + sz * z0;

  std::uint32_t cell[8];
  bool inside[8];
  BlockKey key = 0;
#pragma unroll
  for (int i = 0; i < 8; ++i) {
    const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + (i >> 2);
    inside[i] = x >= 0 && y >= 0 && z >= 0 && x < p.size.x && y < p.size.y && z < p.size.z;
    cell[i] = inside[i] ? (p.cells[origin + block_cell_offset(i, sy, sz)] & 7u) : kOutsideCell;
    key |= cell[i] << (3 * i);
  }
  // A permutation of 8 equal cells changes nothing: skip the lookup (the CPU skips such runs too).
  if (key == cell[0] * kUniformKeyUnit) return;

  BlockKey next = 0;
  if constexpr (kRandom) {
    const auto map = horizontal_symmetry(int(block_random(p.seed, p.tick, x0, y0, z0) & 7u));
    BlockKey viewed = 0;
#pragma unroll
    for (int i = 0; i < 8; ++i) viewed |= cell[i] << (3 * map[i]);
    const BlockKey after = __ldg(p.result + viewed);
#pragma unroll
    for (int i = 0; i < 8; ++i) next |= ((after >> (3 * map[i])) & 7u) << (3 * i);
  } else {
    next = __ldg(p.result + key);
  }
  if (next == key) return;
#pragma unroll
  for (int i = 0; i < 8; ++i) {
    const std::uint32_t value = (next >> (3 * i)) & 7u;
    if (inside[i] && value != cell[i]) p.cells[origin + block_cell_offset(i, sy, sz)] = std::uint8_t(value);
  }
}

/// Grid and block shape of the step kernel for a grid of `size`, the same for all 8 offsets (the
/// largest block counts; threads past a tick's counts return at once).
struct StepShape {
  dim3 grid;   ///< CUDA blocks: (rows of x blocks, y blocks, z layers)
  dim3 block;  ///< threads: a power of two >= 32 along x, the rest of kStepThreads along y
};

/// The launch shape for a grid of `size`: threads along x cover the x blocks (at most
/// kStepThreads), the remaining threads of the CUDA block cover further rows along y.
inline StepShape step_shape(Int3 size) {
  const int bxn = block_count(size.x, 1), byn = block_count(size.y, 1), bzn = block_count(size.z, 1);
  int bdx = 32;
  while (bdx < bxn && bdx < kStepThreads) bdx *= 2;
  const int bdy = kStepThreads / bdx;
  return {dim3(unsigned((bxn + bdx - 1) / bdx), unsigned((byn + bdy - 1) / bdy), unsigned(bzn)),
          dim3(unsigned(bdx), unsigned(bdy), 1)};
}

/// Enqueues one tick (p.tick) on `stream`; checks the launch (BackendError), not its completion.
inline void launch_step(const StepParams& p, bool random_symmetry, const StepShape& shape, cudaStream_t stream) {
  if (random_symmetry)
    step_kernel<true><<<shape.grid, shape.block, 0, stream>>>(p);
  else
    step_kernel<false><<<shape.grid, shape.block, 0, stream>>>(p);
  check_launch("step kernel launch");
}

}  // namespace granular::cuda
