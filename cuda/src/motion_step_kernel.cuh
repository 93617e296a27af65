#pragma once
/// @file motion_step_kernel.cuh
/// One sub-step of the motion model (granular/motion.hpp) on the device: the block helpers shared
/// by the dense and the sparse motion kernels (sparse_motion_kernel.cuh), and the dense kernel.
///
/// A tick of a motion rule set is MotionParams::substeps launches, sub-step s a full Margolus
/// partition at motion::motion_offset(tick, s, seed, random_axis_order). Every block's 8 bytes
/// (material and motion level) become motion::step_block(bytes, ...), the very function the CPU
/// backend runs, looked up in the transition table itself (not the result table: the step maps
/// each cell's byte, level included, to its destination). Identity with the CPU holds by
/// construction as in step_kernel.cuh: same offsets, block origins, draws and table; blocks of one
/// sub-step are disjoint.
///
/// Threads take groups of kGroupBlocks blocks of a row as step_kernel does. A group inside the
/// grid is read as four 8-byte row segments and skipped when its 32 bytes are equal and
/// motion::uniform_block_unchanged says such a block stays as it is (any but grains, and grains
/// but in sub-step 0, which sets their phases); a block that holds no grain step_block would look
/// at (none at all in sub-step 0, none in the top layer after it) is left as it is without a draw.
/// A group touching the edge goes block by block: cells outside read as solid and are never
/// written. Only changed bytes are stored. The helpers take a Notes policy: NoNotes for the dense
/// kernel (compiles to nothing), BrickNotes (sparse_motion_kernel.cuh) for the sparse kernel's
/// per-brick flags, which notes every block but those of a skipped uniform group, as the CPU's
/// sparse step does.
/// The non-motion kernels (step_kernel.cuh, step_pair_kernel.cuh, sparse_step_kernel.cuh) keep
/// their own bodies: their machine code and timings were measured.
/// Kernels and launchers here are static: every translation unit including this gets its own copy.

#include <cuda_runtime.h>

#include <cstdint>

#include "cuda_check.cuh"
#include "granular/block.hpp"
#include "granular/geometry.hpp"
#include "granular/motion.hpp"
#include "step/motion_block.hpp"
#include "step_kernel.cuh"

namespace granular::cuda {

/// Everything one sub-step of the motion kernels reads.
struct MotionStepParams {
  std::uint8_t* cells = nullptr;        ///< the grid on the device (as StepParams::cells)
  Int3 size{};                          ///< grid extent
  const Transition* table = nullptr;    ///< device transition table of motion::motion_rule
  motion::SubStep sub{};                ///< seed, tick, sub-step and the rule set's motion parameters
  bool random_axis_order = false;       ///< RuleSet::random_axis_order (motion::motion_offset)
};

/// The partition offset of the sub-step `p` steps.
__device__ inline BlockOffset motion_offset_of(const MotionStepParams& p) {
  return motion::motion_offset(p.sub.tick, p.sub.substep, p.sub.seed, p.random_axis_order);
}

/// True when step_block may change a block in sub-step `substep`: it holds a grain (sub-step 0
/// sets every grain's phase), or after sub-step 0 a grain in its top layer (bytes 4..7): step_block
/// leaves any other block as it is.
__device__ inline bool may_change(std::uint64_t bytes, int substep) {
  constexpr std::uint64_t kEveryByte = 0x0101010101010101ull;
  std::uint64_t grain = (bytes & (kEveryByte * kMaterialMask)) ^ (kEveryByte * motion::kGrain);  // 0 where a grain is
  if (substep != 0) grain |= 0x01010101u;                                                        // the bottom layer
  return ((grain - kEveryByte) & ~grain & (kEveryByte * 0x80u)) != 0;
}

/// The block's 8 bytes (cell i in byte i) after the sub-step; (x0, y0, z0) is its lowest corner.
__device__ inline std::uint64_t motion_next(const MotionStepParams& p, std::uint64_t bytes, int x0, int y0, int z0) {
  if (!may_change(bytes, p.sub.substep)) return bytes;
  return motion::step_block(bytes, p.sub, x0, y0, z0, [&](BlockKey key) { return __ldg(p.table + key); });
}

/// True when 8 bytes all equal `byte` (the low byte of `bytes`) and such a block stays as it is in
/// the sub-step (motion::uniform_block_unchanged), which may then skip it.
__device__ inline bool uniform_unchanged(std::uint64_t bytes, int substep) {
  return bytes == (bytes & 0xFFu) * 0x0101010101010101ull &&
         motion::uniform_block_unchanged(std::uint32_t(bytes & 0xFFu), substep);
}

/// The Notes policy of the dense kernel: records nothing.
struct NoNotes {
  /// A stepped block's bytes before the sub-step.
  __device__ void block(std::uint64_t) {}
  /// Cell (x, y, z), inside the grid, changed.
  __device__ void changed(int, int, int) {}
};

/// Writes the bytes of `after` that differ from `before` to the block whose cell 0 is at linear
/// index `origin` and lowest corner (x0, y0, z0), where `inside` has bit i set (cells outside the
/// grid are never written), and notes each changed cell.
template <class Notes>
__device__ inline void store_motion_block(const MotionStepParams& p, std::int64_t origin, int x0, int y0, int z0,
                                          std::uint64_t before, std::uint64_t after, unsigned inside, Notes& notes) {
  const std::int64_t sy = p.size.x, sz = sy * p.size.y;
  const std::uint64_t diff = before ^ after;
#pragma unroll
  for (int i = 0; i < 8; ++i)
    if (((inside >> i) & 1u) != 0 && ((diff >> (8 * i)) & 0xFFu) != 0) {
      p.cells[origin + block_cell_offset(i, sy, sz)] = std::uint8_t(after >> (8 * i));
      notes.changed(x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + (i >> 2));
    }
}

/// One block, any position: cells outside the grid read as solid (byte kOutsideCell) and are
/// never written.
template <class Notes>
__device__ inline void motion_edge_block(const MotionStepParams& p, int x0, int y0, int z0, Notes& notes) {
  const std::int64_t sy = p.size.x, sz = sy * p.size.y;
  const std::int64_t origin = std::int64_t(x0) + sy * y0 + sz * z0;
  std::uint64_t bytes = 0;
  unsigned inside = 0;
#pragma unroll
  for (int i = 0; i < 8; ++i) {
    const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + (i >> 2);
    const bool in = x >= 0 && y >= 0 && z >= 0 && x < p.size.x && y < p.size.y && z < p.size.z;
    const std::uint64_t byte = in ? p.cells[origin + block_cell_offset(i, sy, sz)] : kOutsideCell;
    inside |= unsigned(in) << i;
    bytes |= byte << (8 * i);
  }
  notes.block(bytes);
  if (uniform_unchanged(bytes, p.sub.substep)) return;
  const std::uint64_t after = motion_next(p, bytes, x0, y0, z0);
  if (after != bytes) store_motion_block(p, origin, x0, y0, z0, bytes, after, inside, notes);
}

/// kGroupBlocks blocks starting at (x0, y0, z0), all of whose cells lie inside the grid.
template <class Notes>
__device__ inline void motion_inside_group(const MotionStepParams& p, int x0, int y0, int z0, Notes& notes) {
  constexpr std::uint64_t kEveryByte = 0x0101010101010101ull;
  const std::int64_t sy = p.size.x, sz = sy * p.size.y;
  const std::int64_t origin = std::int64_t(x0) + sy * y0 + sz * z0;
  // Row r holds the group's cells at (dy, dz) = (r & 1, r >> 1): cells 2r and 2r+1 of each block.
  std::uint64_t row[4];
#pragma unroll
  for (int r = 0; r < 4; ++r) row[r] = load_bytes8(p.cells, origin + sy * (r & 1) + sz * (r >> 1));
  const std::uint64_t same = (row[0] & 0xFFu) * kEveryByte;
  if (((row[0] ^ same) | (row[1] ^ same) | (row[2] ^ same) | (row[3] ^ same)) == 0 &&
      motion::uniform_block_unchanged(std::uint32_t(row[0] & 0xFFu), p.sub.substep))
    return;
#pragma unroll
  for (int k = 0; k < kGroupBlocks; ++k) {
    std::uint64_t v = 0;
#pragma unroll
    for (int r = 0; r < 4; ++r) v |= ((row[r] >> (16 * k)) & 0xFFFFu) << (16 * r);
    notes.block(v);
    if (uniform_unchanged(v, p.sub.substep)) continue;
    const std::uint64_t after = motion_next(p, v, x0 + 2 * k, y0, z0);
    if (after != v) store_motion_block(p, origin + 2 * k, x0 + 2 * k, y0, z0, v, after, 0xFFu, notes);
  }
}

/// One sub-step over every block: thread (x, y) of CUDA block (bx, by, bz) takes the group of
/// kGroupBlocks blocks starting at block ((bx * blockDim.x + x) * kGroupBlocks, by * blockDim.y +
/// y, bz), as step_kernel (launched with step_shape).
static __global__ void __launch_bounds__(kStepThreads) motion_step_kernel(MotionStepParams p) {
  const BlockOffset o = motion_offset_of(p);
  const int first = int(blockIdx.x * blockDim.x + threadIdx.x) * kGroupBlocks;
  const int by = int(blockIdx.y * blockDim.y + threadIdx.y);
  const int bz = int(blockIdx.z);
  const int blocks_x = block_count(p.size.x, o.x);
  if (first >= blocks_x || by >= block_count(p.size.y, o.y) || bz >= block_count(p.size.z, o.z)) return;
  const int x0 = 2 * first - o.x, y0 = 2 * by - o.y, z0 = 2 * bz - o.z;
  NoNotes notes;
  if (x0 >= 0 && x0 + 2 * kGroupBlocks <= p.size.x && y0 >= 0 && y0 + 1 < p.size.y && z0 >= 0 && z0 + 1 < p.size.z) {
    motion_inside_group(p, x0, y0, z0, notes);
    return;
  }
  for (int k = 0; k < kGroupBlocks && first + k < blocks_x; ++k) motion_edge_block(p, x0 + 2 * k, y0, z0, notes);
}

/// Enqueues one sub-step (p.sub) over every block on `stream`; checks the launch (BackendError),
/// not its completion.
static inline void launch_motion_step(const MotionStepParams& p, const StepShape& shape, cudaStream_t stream) {
  motion_step_kernel<<<shape.grid, shape.block, 0, stream>>>(p);
  check_launch("motion step kernel launch");
}

}  // namespace granular::cuda
