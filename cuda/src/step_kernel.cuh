#pragma once
/// @file step_kernel.cuh
/// One tick of the Margolus partition on the device. Shared by the CUDA backend and the CUDA
/// benchmark, so both run exactly the same code.
///
/// Each thread takes a group of kGroupBlocks consecutive blocks of one row (same y0, z0). A group
/// entirely inside the grid is read as four 8-byte row segments (each from two aligned words), and
/// skipped when all 32 cells are equal; its blocks are then packed to keys, looked up and only the
/// changed cells stored. A group touching the grid's edge goes block by block through the general
/// path, where cells outside the grid read as solid and are never written.
///
/// Identity with the CPU backend (cpu_step.cpp) holds by construction: the offset, block counts,
/// block origins, random draw and symmetry maps come from the same constexpr functions of
/// block.hpp; the key is looked up in the same result table (derived on the device from the same
/// transition table); blocks of one tick are disjoint, so the order of work does not matter. With
/// random symmetry the block is viewed in the drawn frame (cell i moves to map[i]), looked up, and
/// moved back (the cell at map[i] returns to i), which is what the CPU's forward and inverse key
/// tables do. A block of 8 equal cells is left alone: any permutation of it is itself.
/// The recording form (step_record_kernel, for dense-recording ticks of sparse mode) also records,
/// for the blocks it steps, the flags the sparse step kernel sets (activity_record.cuh), through
/// the kRecord forms of the block helpers; their plain forms compile to the plain stepping code.
/// Kernels and launchers here are static: every translation unit including this gets its own copy.

#include <cuda_runtime.h>

#include <cstdint>

#include "activity_record.cuh"
#include "cuda_check.cuh"
#include "granular/block.hpp"
#include "granular/geometry.hpp"

namespace granular::cuda {

/// Threads per CUDA block of the step kernel.
inline constexpr int kStepThreads = 256;

/// Consecutive blocks along x stepped by one thread (8 bytes of each of the group's 4 rows).
inline constexpr int kGroupBlocks = 4;
static_assert(kBrickBlocks % kGroupBlocks == 0, "a thread's group of blocks has a single owner brick");

/// The state of a cell outside the grid (Material::Solid).
inline constexpr std::uint32_t kOutsideCell = 1;

/// Key of a block whose 8 cells all hold 1 (multiply by a state to get its uniform key).
inline constexpr BlockKey kUniformKeyUnit = 0x249249u;  // octal 11111111

/// Everything one tick of the step kernel reads.
struct StepParams {
  std::uint8_t* cells = nullptr;     ///< the grid on the device, x fastest, one byte per cell, in a
                                     ///< buffer of whole 8-byte words (cuda_device.cuh)
  Int3 size{};                       ///< grid extent
  const BlockKey* result = nullptr;  ///< device result table: per key, the key after its transition
  std::uint64_t seed = 0;            ///< world seed (random symmetry)
  std::uint64_t tick = 0;            ///< the tick computed (selects the offset)
  bool random_axis_order = false;    ///< draw the offset order per 8-tick cycle (block_offset)
};

/// Linear index offset of block cell i from the block's lowest corner.
__device__ inline std::int64_t block_cell_offset(int i, std::int64_t sy, std::int64_t sz) {
  return std::int64_t(i & 1) + sy * ((i >> 1) & 1) + sz * (i >> 2);
}

/// The key of the block at (x0, y0, z0) after the rule of tick `tick` (`key` is its key now).
template <bool kRandom>
__device__ inline BlockKey next_key_at(const StepParams& p, std::uint64_t tick, BlockKey key, int x0, int y0, int z0) {
  if constexpr (kRandom) {
    const auto map = horizontal_symmetry(int(block_random(p.seed, tick, x0, y0, z0) & 7u));
    BlockKey viewed = 0;
#pragma unroll
    for (int i = 0; i < 8; ++i) viewed |= ((key >> (3 * i)) & 7u) << (3 * map[i]);
    const BlockKey after = __ldg(p.result + viewed);
    BlockKey next = 0;
#pragma unroll
    for (int i = 0; i < 8; ++i) next |= ((after >> (3 * map[i])) & 7u) << (3 * i);
    return next;
  } else {
    return __ldg(p.result + key);
  }
}

/// The key of the block at (x0, y0, z0) after this tick's (p.tick's) rule.
template <bool kRandom>
__device__ inline BlockKey next_key(const StepParams& p, BlockKey key, int x0, int y0, int z0) {
  return next_key_at<kRandom>(p, p.tick, key, x0, y0, z0);
}

/// One block, any position: cells outside the grid read as solid and are never written. With
/// kRecord, notes its key and changed cells in `*f` / `*rec`.
template <bool kRandom, bool kRecord = false>
__device__ inline void step_edge_block(const StepParams& p, int x0, int y0, int z0, const ActivityRecord* rec = nullptr,
                                       OwnerFlags* f = nullptr) {
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
  if (key == cell[0] * kUniformKeyUnit) return;
  const BlockKey next = next_key<kRandom>(p, key, x0, y0, z0);
  if constexpr (kRecord) record_key<kRandom>(*rec, *f, key, next);
  if (next == key) return;
#pragma unroll
  for (int i = 0; i < 8; ++i) {
    const std::uint32_t value = (next >> (3 * i)) & 7u;
    if (inside[i] && value != cell[i]) {
      p.cells[origin + block_cell_offset(i, sy, sz)] = std::uint8_t(value);
      if constexpr (kRecord) record_changed_cell(*rec, *f, x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + (i >> 2));
    }
  }
}

/// The 8 bytes of the grid buffer starting at byte `at` (any alignment), from the one or two
/// aligned words holding them; both lie inside the buffer since the 8 bytes do.
__device__ inline std::uint64_t load_bytes8(const std::uint8_t* cells, std::int64_t at) {
  const auto* word = reinterpret_cast<const std::uint64_t*>(cells + (at & ~std::int64_t(7)));
  const unsigned shift = unsigned(at & 7) * 8;
  const std::uint64_t low = word[0];
  return shift == 0 ? low : (low >> shift) | (word[1] << (64 - shift));
}

/// Block order bytes (cell i in byte i, each < 8) packed to a key: cpu_step.cpp's pack_key.
__device__ inline BlockKey pack_block_bytes(std::uint64_t v) {
  std::uint64_t t = (v | (v >> 5)) & 0x003F003F003F003Full;
  t = (t | (t >> 10)) & 0x00000FFF00000FFFull;
  return BlockKey((t | (t >> 20)) & 0xFFFFFFu);
}

/// kGroupBlocks blocks starting at (x0, y0, z0), all of whose cells lie inside the grid. With
/// kRecord, notes their keys and changed cells in `*f` / `*rec`.
template <bool kRandom, bool kRecord = false>
__device__ inline void step_inside_group(const StepParams& p, int x0, int y0, int z0,
                                         const ActivityRecord* rec = nullptr, OwnerFlags* f = nullptr) {
  constexpr std::uint64_t kEveryByte = 0x0101010101010101ull;
  const std::int64_t sy = p.size.x, sz = sy * p.size.y;
  const std::int64_t origin = std::int64_t(x0) + sy * y0 + sz * z0;
  // Row r holds the group's cells at (dy, dz) = (r & 1, r >> 1): cells 2r and 2r+1 of each block.
  std::uint64_t row[4];
#pragma unroll
  for (int r = 0; r < 4; ++r) row[r] = load_bytes8(p.cells, origin + sy * (r & 1) + sz * (r >> 1)) & (7 * kEveryByte);
  const std::uint64_t same = (row[0] & 0xFFu) * kEveryByte;
  if (((row[0] ^ same) | (row[1] ^ same) | (row[2] ^ same) | (row[3] ^ same)) == 0) return;
#pragma unroll
  for (int k = 0; k < kGroupBlocks; ++k) {
    std::uint64_t v = 0;
#pragma unroll
    for (int r = 0; r < 4; ++r) v |= ((row[r] >> (16 * k)) & 0xFFFFu) << (16 * r);
    if (v == (v & 0xFFu) * kEveryByte) continue;
    const BlockKey key = pack_block_bytes(v);
    const BlockKey next = next_key<kRandom>(p, key, x0 + 2 * k, y0, z0);
    if constexpr (kRecord) record_key<kRandom>(*rec, *f, key, next);
    if (next == key) continue;
#pragma unroll
    for (int i = 0; i < 8; ++i) {
      const std::uint32_t value = (next >> (3 * i)) & 7u;
      if (value != ((key >> (3 * i)) & 7u)) {
        p.cells[origin + 2 * k + block_cell_offset(i, sy, sz)] = std::uint8_t(value);
        if constexpr (kRecord)
          record_changed_cell(*rec, *f, x0 + 2 * k + (i & 1), y0 + ((i >> 1) & 1), z0 + (i >> 2));
      }
    }
  }
}

/// The tick's blocks: thread (x, y) of CUDA block (bx, by, bz) takes the group of kGroupBlocks
/// blocks starting at block ((bx * blockDim.x + x) * kGroupBlocks, by * blockDim.y + y, bz), so a
/// warp reads 32 consecutive 8-byte segments of each of 4 rows.
template <bool kRandom>
static __global__ void __launch_bounds__(kStepThreads) step_kernel(StepParams p) {
  const BlockOffset o = block_offset(p.tick, p.seed, p.random_axis_order);
  const int first = int(blockIdx.x * blockDim.x + threadIdx.x) * kGroupBlocks;
  const int by = int(blockIdx.y * blockDim.y + threadIdx.y);
  const int bz = int(blockIdx.z);
  const int blocks_x = block_count(p.size.x, o.x);
  if (first >= blocks_x || by >= block_count(p.size.y, o.y) || bz >= block_count(p.size.z, o.z)) return;
  const int x0 = 2 * first - o.x, y0 = 2 * by - o.y, z0 = 2 * bz - o.z;
  if (x0 >= 0 && x0 + 2 * kGroupBlocks <= p.size.x && y0 >= 0 && y0 + 1 < p.size.y && z0 >= 0 && z0 + 1 < p.size.z) {
    step_inside_group<kRandom>(p, x0, y0, z0);
    return;
  }
  for (int k = 0; k < kGroupBlocks && first + k < blocks_x; ++k) step_edge_block<kRandom>(p, x0 + 2 * k, y0, z0);
}

/// step_kernel recording the sparse flags in `rec` (activity_record.cuh): the same blocks through
/// the kRecord forms of the same helpers; the thread's 4 blocks have one owner brick, whose flags
/// collect in registers and are stored once. (A body shared with step_kernel, inlined into both,
/// changes step_kernel's machine code; the plain kernel keeps its own.)
template <bool kRandom>
static __global__ void __launch_bounds__(kStepThreads) step_record_kernel(StepParams p, ActivityRecord rec) {
  const BlockOffset o = block_offset(p.tick, p.seed, p.random_axis_order);
  const int first = int(blockIdx.x * blockDim.x + threadIdx.x) * kGroupBlocks;
  const int by = int(blockIdx.y * blockDim.y + threadIdx.y);
  const int bz = int(blockIdx.z);
  const int blocks_x = block_count(p.size.x, o.x);
  if (first >= blocks_x || by >= block_count(p.size.y, o.y) || bz >= block_count(p.size.z, o.z)) return;
  const int x0 = 2 * first - o.x, y0 = 2 * by - o.y, z0 = 2 * bz - o.z;
  OwnerFlags f;
  f.owner = {owner_brick(first, rec.bricks.x), owner_brick(by, rec.bricks.y), owner_brick(bz, rec.bricks.z)};
  if (x0 >= 0 && x0 + 2 * kGroupBlocks <= p.size.x && y0 >= 0 && y0 + 1 < p.size.y && z0 >= 0 && z0 + 1 < p.size.z) {
    step_inside_group<kRandom, true>(p, x0, y0, z0, &rec, &f);
  } else {
    for (int k = 0; k < kGroupBlocks && first + k < blocks_x; ++k)
      step_edge_block<kRandom, true>(p, x0 + 2 * k, y0, z0, &rec, &f);
  }
  flush_owner(rec, f);
}

/// Grid and block shape of the step kernel for a grid of `size`, the same for all 8 offsets (the
/// largest block counts; threads past a tick's counts return at once).
struct StepShape {
  dim3 grid;   ///< CUDA blocks: (row pieces along x, rows along y, block layers along z)
  dim3 block;  ///< threads: a power of two >= 32 along x, the rest of kStepThreads along y
};

/// The launch shape for a grid of `size`: threads along x cover the row's block groups (at most
/// kStepThreads of them), the remaining threads of the CUDA block cover further rows along y.
inline StepShape step_shape(Int3 size) {
  const int groups = (block_count(size.x, 1) + kGroupBlocks - 1) / kGroupBlocks;
  const int rows = block_count(size.y, 1), layers = block_count(size.z, 1);
  int bdx = 32;
  while (bdx < groups && bdx < kStepThreads) bdx *= 2;
  const int bdy = kStepThreads / bdx;
  return {dim3(unsigned((groups + bdx - 1) / bdx), unsigned((rows + bdy - 1) / bdy), unsigned(layers)),
          dim3(unsigned(bdx), unsigned(bdy), 1)};
}

/// Enqueues one tick (p.tick) on `stream`, recording the sparse flags in `*record` when given;
/// checks the launch (BackendError), not its completion.
static inline void launch_step(const StepParams& p, bool random_symmetry, const StepShape& shape, cudaStream_t stream,
                               const ActivityRecord* record = nullptr) {
  if (record != nullptr) {
    if (random_symmetry)
      step_record_kernel<true><<<shape.grid, shape.block, 0, stream>>>(p, *record);
    else
      step_record_kernel<false><<<shape.grid, shape.block, 0, stream>>>(p, *record);
    check_launch("step record kernel launch");
    return;
  }
  if (random_symmetry)
    step_kernel<true><<<shape.grid, shape.block, 0, stream>>>(p);
  else
    step_kernel<false><<<shape.grid, shape.block, 0, stream>>>(p);
  check_launch("step kernel launch");
}

}  // namespace granular::cuda
