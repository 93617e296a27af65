#pragma once
/// @file sparse_motion_kernel.cuh
/// One sub-step of the motion model over the awake bricks: sparse_step_kernel's walk of the brick
/// list and its bookkeeping (dirty and changed flags, activity counters; sparse_step_kernel.cuh)
/// around the motion block helpers (motion_step_kernel.cuh).
///
/// A block marks its owner brick dirty unless it is *quiet*: every grain in it at rest (level 0 and
/// the phase sub-step 0 gives it) and its rest key (motion::rest_key) inert under the rule set's
/// variants. A quiet block stays as it is in every sub-step, whatever the draws (motion_block.hpp),
/// which is what lets a brick of quiet blocks sleep. Every stepped block is noted but those of a
/// skipped uniform group (motion_step_kernel.cuh), the CPU's rule (cpu_sparse_step.cpp) on groups
/// of 4 blocks where the CPU's are 8: the awake bricks, and so the activity figures, could differ
/// from the CPU's only where a uniform group of grains, skipped in a sub-step other than 0, lies in
/// a non-uniform group of 8 (the cells are exact either way: such a block does not change, and sub-
/// step 0 notes it). Changed cells flag their bricks as in the sparse step kernel.
///
/// The bricks are counted into the activity counters once per tick (`count`: the tick's first
/// sub-step; the list changes only at a cycle's end, after a tick's last sub-step, or by a tool,
/// between step() calls). The cycle's end runs after the last sub-step of a tick t with t % 8 == 7
/// (launch_end_cycle).

#include <cuda_runtime.h>

#include <cstdint>

#include "step/brick_grid.hpp"
#include "cuda_check.cuh"
#include "granular/block.hpp"
#include "granular/motion.hpp"
#include "step/motion_block.hpp"
#include "motion_step_kernel.cuh"
#include "sparse_step_kernel.cuh"

namespace granular::cuda {

/// The Notes policy of the sparse motion kernel: one thread's flags for the brick it steps.
struct BrickNotes {
  const SparseParams* s = nullptr;  ///< the sparse state (inert table, changed flags)
  int offset_z = 0;                 ///< the sub-step's partition offset along z (motion::rest_key)
  BrickSeen seen;                   ///< what the thread saw of its brick

  /// A stepped block's bytes before the sub-step: not quiet marks the brick dirty.
  __device__ void block(std::uint64_t bytes) {
    if (seen.non_inert) return;
    bool rest = false;
    const BlockKey key = motion::rest_key(bytes, offset_z, rest);
    if (!rest || ((__ldg(s->inert + (key >> 6)) >> (key & 63u)) & 1u) == 0) seen.non_inert = true;
  }
  /// Cell (x, y, z), inside the grid, changed.
  __device__ void changed(int x, int y, int z) { note_changed_cell(*s, seen, x, y, z); }
};

/// One sub-step (p.sub) over the awake bricks, a CUDA block per brick as sparse_step_kernel
/// (whose body stays its own, measured). `count`: add the bricks to kBrickTicks / kCellTicks;
/// `last_tick`: also to kLastBricks / kLastCells.
static __global__ void __launch_bounds__(kBrickThreads)
    sparse_motion_kernel(MotionStepParams p, SparseParams s, bool count, bool last_tick) {
  __shared__ int any_non_inert, any_changed;
  const BlockOffset o = motion_offset_of(p);
  const int t = int(threadIdx.x);
  const int group = t % kBrickGroups, row = (t / kBrickGroups) % kBrickBlocks, layer = t / (kBrickGroups * kBrickBlocks);
  const unsigned listed = *s.count;
  unsigned long long bricks_done = 0, cells_done = 0;  // thread 0's tally, added once at the end
  for (unsigned entry = blockIdx.x; entry < listed; entry += gridDim.x) {
    if (t == 0) {
      any_non_inert = 0;
      any_changed = 0;
    }
    __syncthreads();
    const std::uint32_t index = s.list[entry];
    BrickNotes notes;
    notes.s = &s;
    notes.offset_z = o.z;
    notes.seen.brick = brick_coords(s.bricks, index);
    const Int3 brick = notes.seen.brick;
    const BlockSpan bx = owned_blocks(brick.x, s.bricks.x, p.size.x, o.x);
    const BlockSpan by = owned_blocks(brick.y, s.bricks.y, p.size.y, o.y);
    const BlockSpan bz = owned_blocks(brick.z, s.bricks.z, p.size.z, o.z);
    for (int kz = bz.first + layer; kz < bz.last; kz += kBrickBlocks) {
      const int z0 = 2 * kz - o.z;
      for (int ky = by.first + row; ky < by.last; ky += kBrickBlocks) {
        const int y0 = 2 * ky - o.y;
        for (int k0 = bx.first + group * kGroupBlocks; k0 < bx.last; k0 += kBrickBlocks) {
          const int x0 = 2 * k0 - o.x;
          const int blocks = bx.last - k0 < kGroupBlocks ? bx.last - k0 : kGroupBlocks;
          if (blocks == kGroupBlocks && x0 >= 0 && x0 + 2 * kGroupBlocks <= p.size.x && y0 >= 0 && y0 + 1 < p.size.y &&
              z0 >= 0 && z0 + 1 < p.size.z)
            motion_inside_group(p, x0, y0, z0, notes);
          else
            for (int k = 0; k < blocks; ++k) motion_edge_block(p, x0 + 2 * k, y0, z0, notes);
        }
      }
    }
    if (notes.seen.non_inert) any_non_inert = 1;
    if (notes.seen.owner_changed) any_changed = 1;
    __syncthreads();
    if (t == 0) {
      if (any_non_inert) s.dirty[index] = 1;
      if (any_changed) s.changed[index] = 1;
      ++bricks_done;
      cells_done += brick_cells(p.size, brick.x, brick.y, brick.z);
    }
    __syncthreads();
  }
  if (t == 0 && count && bricks_done > 0) {
    atomicAdd(s.counters + kBrickTicks, bricks_done);
    atomicAdd(s.counters + kCellTicks, cells_done);
    if (last_tick) {
      atomicAdd(s.counters + kLastBricks, bricks_done);
      atomicAdd(s.counters + kLastCells, cells_done);
    }
  }
}

/// Enqueues one sparse sub-step (p.sub) with `grid` CUDA blocks walking the list; `count` and
/// `last_tick` as sparse_motion_kernel.
static inline void launch_sparse_motion(const MotionStepParams& p, const SparseParams& s, bool count, bool last_tick,
                                        unsigned grid, cudaStream_t stream) {
  sparse_motion_kernel<<<grid, kBrickThreads, 0, stream>>>(p, s, count, last_tick);
  check_launch("sparse motion kernel launch");
}

}  // namespace granular::cuda
