#pragma once
/// @file sparse_kernel.cuh
/// Sparse stepping on the device: one (sub-)step over the list of awake bricks for every Rule
/// (step/block_step.hpp), the per-cycle sleep/wake update, tool wakes, and the inert-key table
/// (docs/design/sparse-stepping.md; the CPU counterpart is cpu_sparse_step.cpp +
/// brick_activity.cpp, with the same rules).
///
/// State, one byte per brick (x fastest): awake (stepped this cycle), dirty (owned a block that was
/// not quiet this cycle, or was touched by a tool), changed (a cell changed since the host last took
/// the flags); plus the compact list of awake bricks and its length, both built on the device so
/// that step(n) enqueues every launch and synchronises once.
///
/// The step kernel runs a fixed grid of CUDA blocks that walk the list (grid-stride over the
/// device-side count): a settled world costs one near-empty launch per step. A CUDA block of
/// kBrickThreads threads steps one brick: thread t takes the group of kGroupBlocks blocks
/// (t % kBrickGroups) of row (t / kBrickGroups) % kBrickBlocks of layer t / (kBrickGroups *
/// kBrickBlocks), and the rows, layers and groups kBrickBlocks further on (the last brick along an
/// axis may own one block more). Blocks are walked with the dense kernel's helpers (block_walk.cuh)
/// through the BrickNotes policy, so the result is the dense kernels' (and the CPU's) bit for bit.
/// Every stepped block is noted but those of a skipped uniform group, the CPU's rule on groups of 4
/// blocks where the CPU's are 8: a skipped uniform group is quiet either way, so the flags agree.

#include <cuda_runtime.h>

#include <cstdint>

#include "block_walk.cuh"
#include "cuda_check.cuh"
#include "granular/extend/block.hpp"
#include "step/brick_grid.hpp"
#include "step/brick_reach.hpp"
#include "step/inert_keys.hpp"

namespace granular::cuda {

/// Groups of kGroupBlocks blocks per brick row.
inline constexpr int kBrickGroups = kBrickBlocks / kGroupBlocks;
static_assert(kBrickBlocks % kGroupBlocks == 0, "a brick row is whole groups");

/// Threads of the sparse step kernel's CUDA block: one per group of one brick.
inline constexpr int kBrickThreads = kBrickGroups * kBrickBlocks * kBrickBlocks;
static_assert(kBrickThreads >= kReachNeighbours, "a thread per neighbour reads the neighbours' reach");

/// CUDA blocks of the sparse kernel a multiprocessor should hold at once: the motion model's kernel
/// then keeps to 80 registers (with a few spilled bytes) instead of 95, which measured 1.6% faster on
/// the 2048^3 bowl (H200) and the same at 1024^3.
inline constexpr int kSparseBlocksPerSM = 6;

/// Threads per CUDA block of the small bookkeeping kernels.
inline constexpr int kActivityThreads = 256;

/// Slots of the activity counters.
enum ActivityCounter : int {
  kBrickTicks = 0,     ///< bricks stepped, summed over the ticks of a step() call
  kCellTicks = 1,      ///< cells of stepped bricks, summed likewise
  kLastBricks = 2,     ///< bricks stepped in the call's last tick
  kLastCells = 3,      ///< cells of those bricks
  kCounterSlots = 4,
};

/// The device state of sparse stepping.
struct SparseParams {
  Int3 bricks{};                          ///< bricks per axis
  std::uint32_t total = 0;                ///< bricks in the grid
  std::uint8_t* awake = nullptr;          ///< per brick: stepped this cycle
  std::uint8_t* dirty = nullptr;          ///< per brick: non-inert key seen / tool this cycle
  std::uint8_t* changed = nullptr;        ///< per brick: a cell changed (until the host takes it)
  unsigned* reach = nullptr;              ///< per brick: its reach in the tick (brick_reach.hpp; motion
                                          ///< model only; a word, so that it grows by a reduction)
  std::uint32_t* list = nullptr;          ///< the awake bricks, in any order
  unsigned* count = nullptr;              ///< length of the list
  unsigned long long* counters = nullptr; ///< ActivityCounter slots
};

/// The Notes policy of the sparse kernel: one thread's flags for the brick it steps.
struct BrickNotes {
  /// What it is built from.
  using Params = SparseParams;

  /// The notes of a thread stepping brick `brick`.
  /// The brick's dirty byte (set earlier in the cycle) starts it as seen non-inert: its blocks need
  /// no quiet test then.
  __device__ BrickNotes(const SparseParams& params, Int3 brick_coords, std::uint32_t index)
      : s(params), brick(brick_coords), non_inert(params.dirty[index] != 0) {}

  /// A stepped block that is not quiet marks the brick dirty, and adds to its reach.
  template <class Rule>
  __device__ void block(const Rule& rule, std::uint64_t before, std::uint64_t after) {
    if (!non_inert && !rule.quiet(before, after)) non_inert = true;
    if constexpr (Rule::kReach) {
      const std::uint32_t added = rule.reach_added(before, after);
      if (added > reach) reach = added;
    }
  }

  /// A stepped block holds a velocity (side plane): it is not quiet.
  __device__ void moving() { non_inert = true; }

  /// Records that cell (x, y, z) changed: in the brick it is collected per CUDA block; a cell of a
  /// neighbour (a straddling block) is flagged at once.
  __device__ void changed(int x, int y, int z) {
    if (flag_changed_cell(brick, s.bricks, s.changed, x, y, z)) owner_changed = true;
  }

  /// The CUDA block collects the flags (sparse_kernel).
  __device__ void flush() {}

  const SparseParams& s;       ///< the sparse state
  Int3 brick;                  ///< the brick's coordinates
  bool non_inert = false;      ///< a block was not quiet
  bool owner_changed = false;  ///< a cell of the brick itself changed
  std::uint32_t reach = 0;     ///< the largest reach its blocks added (Rule::kReach)
};

/// True when `rule` leaves brick `index` (at `brick`) out of its sub-step: the brick is dirty already
/// and idle (brick_reach.hpp). Thread t < kReachNeighbours reads neighbour t's reach; the answer is the
/// CUDA block's, the same for every thread.
template <class Rule>
__device__ inline bool leaves_out(const Rule& rule, const SparseParams& s, Int3 brick, std::uint32_t index) {
  if constexpr (!Rule::kReach) {
    return false;
  } else {
    if (!rule.may_idle()) return false;
    // The neighbours' reaches load beside the dirty byte, not after it: one wait, not two.
    std::uint32_t neighbour = 0;
    const int t = int(threadIdx.x);
    const bool busy = t < kReachNeighbours && reach_neighbour(s.bricks, brick, t, neighbour) &&
                      !rule.idle(s.reach[neighbour]);
    return s.dirty[index] != 0 && __syncthreads_or(busy) == 0;
  }
}

/// One (sub-)step of `rule` over the awake bricks (see the file comment). `count`: add the bricks to
/// kBrickTicks / kCellTicks (once per tick: at a motion model's first sub-step); `last_tick`: also to
/// kLastBricks / kLastCells.
template <class Rule>
static __global__ void __launch_bounds__(kBrickThreads, kSparseBlocksPerSM)
    sparse_kernel(DeviceCells g, Rule rule, SparseParams s, bool count, bool last_tick) {
  __shared__ int any_non_inert, any_changed;
  __shared__ unsigned brick_reach;
  const BlockOffset o = rule.offset;
  const int t = int(threadIdx.x);
  const int group = t % kBrickGroups, row = (t / kBrickGroups) % kBrickBlocks, layer = t / (kBrickGroups * kBrickBlocks);
  const unsigned listed = *s.count;
  unsigned long long bricks_done = 0, cells_done = 0;  // thread 0's tally, added once at the end
  for (unsigned entry = blockIdx.x; entry < listed; entry += gridDim.x) {
    if (t == 0) {
      any_non_inert = 0;
      any_changed = 0;
      brick_reach = 0;
    }
    __syncthreads();
    const std::uint32_t index = s.list[entry];
    if (leaves_out(rule, s, brick_coords(s.bricks, index), index)) continue;
    BrickNotes notes(s, brick_coords(s.bricks, index), index);
    const Int3 brick = notes.brick;
    const BlockSpan bx = owned_blocks(brick.x, s.bricks.x, g.size.x, o.x);
    const BlockSpan by = owned_blocks(brick.y, s.bricks.y, g.size.y, o.y);
    const BlockSpan bz = owned_blocks(brick.z, s.bricks.z, g.size.z, o.z);
    for (int kz = bz.first + layer; kz < bz.last; kz += kBrickBlocks) {
      const int z0 = 2 * kz - o.z;
      for (int ky = by.first + row; ky < by.last; ky += kBrickBlocks) {
        const int y0 = 2 * ky - o.y;
        for (int k0 = bx.first + group * kGroupBlocks; k0 < bx.last; k0 += kBrickBlocks) {
          const int x0 = 2 * k0 - o.x;
          const int blocks = bx.last - k0 < kGroupBlocks ? bx.last - k0 : kGroupBlocks;
          if (blocks == kGroupBlocks && x0 >= 0 && x0 + 2 * kGroupBlocks <= g.size.x && y0 >= 0 && y0 + 1 < g.size.y &&
              z0 >= 0 && z0 + 1 < g.size.z)
            walk_inside_group(g, rule, x0, y0, z0, notes);
          else
            for (int k = 0; k < blocks; ++k) walk_edge_block(g, rule, x0 + 2 * k, y0, z0, notes);
        }
      }
    }
    if (notes.non_inert) any_non_inert = 1;
    if (notes.owner_changed) any_changed = 1;
    if constexpr (Rule::kReach)
      if (notes.reach > 0) atomicMax(&brick_reach, notes.reach);
    __syncthreads();
    if (t == 0) {
      if (any_non_inert) s.dirty[index] = 1;
      if (any_changed) s.changed[index] = 1;
      if constexpr (Rule::kReach) {
        if (rule.reach_restarts())
          s.reach[index] = brick_reach;
        else if (brick_reach > 0)
          atomicMax(s.reach + index, brick_reach);  // a reduction: nothing waits for it
      }
      ++bricks_done;
      cells_done += brick_cells(g.size, brick.x, brick.y, brick.z);
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

/// Sets awake for brick `index` and its up to 26 neighbours.
__device__ inline void wake_neighbourhood(const SparseParams& s, std::uint32_t index) {
  const Int3 b = brick_coords(s.bricks, index);
  for (int z = b.z > 0 ? b.z - 1 : 0; z <= (b.z + 1 < s.bricks.z ? b.z + 1 : b.z); ++z)
    for (int y = b.y > 0 ? b.y - 1 : 0; y <= (b.y + 1 < s.bricks.y ? b.y + 1 : b.y); ++y)
      for (int x = b.x > 0 ? b.x - 1 : 0; x <= (b.x + 1 < s.bricks.x ? b.x + 1 : b.x); ++x)
        s.awake[brick_index(s.bricks, x, y, z)] = 1;
}

/// End of a cycle, part 1: awake = 0 everywhere (part 2 grows the dirty set into it).
static __global__ void clear_awake_kernel(SparseParams s) {
  for (std::uint32_t b = blockIdx.x * blockDim.x + threadIdx.x; b < s.total; b += gridDim.x * blockDim.x)
    s.awake[b] = 0;
}

/// End of a cycle, part 2 (and tool wakes): every dirty brick wakes its neighbourhood. With
/// `wake_list` (tools) only the `wake_count` listed bricks, which also become dirty.
static __global__ void wake_dirty_kernel(SparseParams s, const std::uint32_t* wake_list, unsigned wake_count) {
  const unsigned n = wake_list != nullptr ? wake_count : s.total;
  for (unsigned i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x) {
    if (wake_list != nullptr) {
      s.dirty[wake_list[i]] = 1;
      wake_neighbourhood(s, wake_list[i]);
    } else if (s.dirty[i]) {
      wake_neighbourhood(s, i);
    }
  }
}

/// The wake of the flagged bricks, as a tool's wake (wake_dirty_kernel with a list): each brick
/// flagged in `flags` (one byte per brick) becomes dirty and wakes its neighbourhood; the flags are
/// cleared.
static __global__ void wake_flagged_kernel(SparseParams s, std::uint8_t* flags) {
  for (std::uint32_t b = blockIdx.x * blockDim.x + threadIdx.x; b < s.total; b += gridDim.x * blockDim.x) {
    if (flags[b] == 0) continue;
    flags[b] = 0;
    s.dirty[b] = 1;
    wake_neighbourhood(s, b);
  }
}

/// Rebuilds the list of awake bricks (s.count must be 0 before).
static __global__ void build_list_kernel(SparseParams s) {
  for (std::uint32_t b = blockIdx.x * blockDim.x + threadIdx.x; b < s.total; b += gridDim.x * blockDim.x)
    if (s.awake[b]) s.list[atomicAdd(s.count, 1u)] = b;
}

/// Adds the bricks of the awake list and their cells (clipped to a grid of `size`) to the activity
/// counters: `ticks` times to kBrickTicks / kCellTicks, and with `last_tick` once to kLastBricks /
/// kLastCells. Dense-recording ticks count with this what the sparse step kernel counts while
/// stepping: the awake bricks, not all of them (the list changes only at a cycle's end or a tool).
static __global__ void count_awake_kernel(SparseParams s, Int3 size, unsigned ticks, bool last_tick) {
  __shared__ unsigned long long block_bricks, block_cells;
  if (threadIdx.x == 0) {
    block_bricks = 0;
    block_cells = 0;
  }
  __syncthreads();
  const unsigned count = *s.count;
  unsigned long long bricks = 0, cells = 0;
  for (unsigned i = blockIdx.x * blockDim.x + threadIdx.x; i < count; i += gridDim.x * blockDim.x) {
    const Int3 b = brick_coords(s.bricks, s.list[i]);
    ++bricks;
    cells += brick_cells(size, b.x, b.y, b.z);
  }
  if (bricks > 0) {
    atomicAdd(&block_bricks, bricks);
    atomicAdd(&block_cells, cells);
  }
  __syncthreads();
  if (threadIdx.x == 0 && block_bricks > 0) {
    atomicAdd(s.counters + kBrickTicks, block_bricks * ticks);
    atomicAdd(s.counters + kCellTicks, block_cells * ticks);
    if (last_tick) {
      atomicAdd(s.counters + kLastBricks, block_bricks);
      atomicAdd(s.counters + kLastCells, block_cells);
    }
  }
}

/// The inert-key bit table of a result table (inert_keys.hpp), one 64-key word per thread.
static __global__ void inert_table_kernel(const BlockKey* result, bool random_symmetry, std::uint64_t* table) {
  for (std::uint32_t w = blockIdx.x * blockDim.x + threadIdx.x; w < kInertTableWords; w += gridDim.x * blockDim.x) {
    std::uint64_t bits = 0;
    for (std::uint32_t b = 0; b < 64; ++b)
      if (key_is_inert(BlockKey(w * 64 + b), random_symmetry, result)) bits |= std::uint64_t(1) << b;
    table[w] = bits;
  }
}

/// CUDA blocks for a bookkeeping kernel over `n` items.
inline unsigned activity_blocks(std::uint64_t n) {
  const std::uint64_t blocks = (n + kActivityThreads - 1) / kActivityThreads;
  return unsigned(blocks < 4096 ? (blocks > 0 ? blocks : 1) : 4096);
}

/// The CUDA blocks of the sparse kernel of `Rule` a device of `sm_count` multiprocessors runs at
/// once: the list is walked by exactly that many, so no CUDA block waits for another to finish.
template <class Rule>
inline unsigned sparse_resident_blocks(int sm_count) {
  int per_sm = 0;
  check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, sparse_kernel<Rule>, kBrickThreads, 0),
        "cudaOccupancyMaxActiveBlocksPerMultiprocessor (sparse step kernel)");
  return unsigned((per_sm > 0 ? per_sm : 1) * (sm_count > 0 ? sm_count : 1));
}

/// Enqueues one sparse (sub-)step of `rule` with `grid` CUDA blocks walking the list; `count` and
/// `last_tick` as sparse_kernel.
template <class Rule>
static inline void launch_sparse(const DeviceCells& g, const Rule& rule, const SparseParams& s, bool count,
                                 bool last_tick, unsigned grid, cudaStream_t stream) {
  sparse_kernel<Rule><<<grid, kBrickThreads, 0, stream>>>(g, rule, s, count, last_tick);
  check_launch("sparse step kernel launch");
}

/// Enqueues the end of a cycle: awake = dirty grown by one brick, the list rebuilt, dirty cleared.
static inline void launch_end_cycle(const SparseParams& s, cudaStream_t stream) {
  const unsigned blocks = activity_blocks(s.total);
  clear_awake_kernel<<<blocks, kActivityThreads, 0, stream>>>(s);
  check_launch("clear awake kernel launch");
  wake_dirty_kernel<<<blocks, kActivityThreads, 0, stream>>>(s, nullptr, 0);
  check_launch("wake dirty kernel launch");
  check(cudaMemsetAsync(s.count, 0, sizeof(unsigned), stream), "cudaMemsetAsync (brick list count)");
  build_list_kernel<<<blocks, kActivityThreads, 0, stream>>>(s);
  check_launch("build brick list kernel launch");
  check(cudaMemsetAsync(s.dirty, 0, s.total, stream), "cudaMemsetAsync (dirty bricks)");
}

/// Enqueues the wake of the bricks flagged in `flags` (wake_flagged_kernel, which clears them) and
/// the rebuild of the awake list.
static inline void launch_wake_flagged(const SparseParams& s, std::uint8_t* flags, cudaStream_t stream) {
  wake_flagged_kernel<<<activity_blocks(s.total), kActivityThreads, 0, stream>>>(s, flags);
  check_launch("wake flagged bricks kernel launch");
  check(cudaMemsetAsync(s.count, 0, sizeof(unsigned), stream), "cudaMemsetAsync (brick list count)");
  build_list_kernel<<<activity_blocks(s.total), kActivityThreads, 0, stream>>>(s);
  check_launch("build brick list kernel launch");
}

/// Enqueues count_awake_kernel: the awake list counted for `ticks` ticks (`last_tick`: the last of
/// them is the step() call's last) on a grid of `size`.
static inline void launch_count_awake(const SparseParams& s, Int3 size, unsigned ticks, bool last_tick,
                                      cudaStream_t stream) {
  count_awake_kernel<<<activity_blocks(s.total), kActivityThreads, 0, stream>>>(s, size, ticks, last_tick);
  check_launch("count awake bricks kernel launch");
}

/// Enqueues a tool wake of the `count` bricks at device address `bricks`: dirty, their
/// neighbourhoods awake, the list rebuilt.
static inline void launch_wake(const SparseParams& s, const std::uint32_t* bricks, unsigned count, cudaStream_t stream) {
  wake_dirty_kernel<<<activity_blocks(count), kActivityThreads, 0, stream>>>(s, bricks, count);
  check_launch("wake bricks kernel launch");
  check(cudaMemsetAsync(s.count, 0, sizeof(unsigned), stream), "cudaMemsetAsync (brick list count)");
  build_list_kernel<<<activity_blocks(s.total), kActivityThreads, 0, stream>>>(s);
  check_launch("build brick list kernel launch");
}

}  // namespace granular::cuda
