#pragma once
/// @file block_walk.cuh
/// How the CUDA kernels walk blocks, for every Rule (step/block_step.hpp) and Notes policy: the
/// device Platform, one edge block, one group of kGroupBlocks blocks of a row, and the dense kernel
/// (every block of one (sub-)step). The fused pair kernel (pair_kernel.cuh) and the sparse kernel
/// (sparse_kernel.cuh) walk with the same helpers.
///
/// Each thread of the dense kernel takes a group of kGroupBlocks consecutive blocks of one row (same
/// y0, z0). A group entirely inside the grid is read as four 8-byte row segments (each from two
/// aligned words) and skipped when all 32 bytes are equal and the Rule says such a block does not
/// change (Rule::steps_uniform); each block is then stepped with Rule::step and only its changed
/// bytes are stored. A group touching the grid's edge goes block by block: cells outside the grid
/// read as Rule::outside and are never written.
///
/// Identity with the CPU backend holds by construction: the offsets, block origins, random draws and
/// tables are those of block_step.hpp, which the CPU compiles too; blocks of one (sub-)step are
/// disjoint, so the order of work does not matter.
///
/// Notes policies say what a walk records: NoNotes (nothing: compiles to the plain stepping code),
/// OwnerNotes (activity_record.cuh: the sparse flags, for dense-recording steps) and BrickNotes
/// (sparse_kernel.cuh). A Notes object has block(rule, before, after) for every stepped block (not
/// for a uniform block the Rule skips: such a block is quiet), moving() for a block left holding a
/// velocity (a side plane's: not quiet), changed(x, y, z) for every cell inside the grid whose byte
/// or side byte changed, and flush() once the thread is done.
/// Kernels and launchers here are static: every translation unit including this gets its own copy.

#include <cuda_runtime.h>

#include <cstdint>
#include <type_traits>

#include "cuda_check.cuh"
#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"
#include "step/block_step.hpp"
#include "step/brick_grid.hpp"

namespace granular::cuda {

/// The device Platform of the block step: read-only cache loads, symmetries by a per-cell loop.
struct DevicePlatform {
  /// Reads a table entry through the read-only data cache.
  template <class T>
  __device__ static T load(const T* p) {
    return __ldg(p);
  }
  /// The key as seen under symmetry s: cell i moves to map[i].
  __device__ static BlockKey view(BlockKey key, int s) {
    const auto map = horizontal_symmetry(s);
    BlockKey viewed = 0;
#pragma unroll
    for (int i = 0; i < 8; ++i) viewed |= ((key >> (3 * i)) & 7u) << (3 * map[i]);
    return viewed;
  }
  /// The block step's byte operations (block_bytes.hpp) through the byte permute instruction.
  struct ByteOps {
    /// lookup_bytes: each half's 4 materials packed to the nibbles of a selector into the table.
    __device__ static std::uint64_t lookup(std::uint64_t table, std::uint64_t bytes) {
      const std::uint32_t lo = std::uint32_t(bytes) & 0x07070707u, hi = std::uint32_t(bytes >> 32) & 0x07070707u;
      const std::uint32_t t0 = std::uint32_t(table), t1 = std::uint32_t(table >> 32);
      const std::uint32_t sel_lo = __byte_perm(lo | (lo >> 4), 0u, 0x4420u);
      const std::uint32_t sel_hi = __byte_perm(hi | (hi >> 4), 0u, 0x4420u);
      return std::uint64_t(__byte_perm(t0, t1, sel_lo)) | (std::uint64_t(__byte_perm(t0, t1, sel_hi)) << 32);
    }
    /// gather_bytes: the low and the high nibbles of `from` select the result's two halves.
    __device__ static std::uint64_t gather(std::uint64_t bytes, std::uint32_t from) {
      const std::uint32_t b0 = std::uint32_t(bytes), b1 = std::uint32_t(bytes >> 32);
      return std::uint64_t(__byte_perm(b0, b1, from & 0xFFFFu)) | (std::uint64_t(__byte_perm(b0, b1, from >> 16)) << 32);
    }
  };
  /// The inverse of view: the cell at map[i] returns to i.
  __device__ static BlockKey unview(BlockKey key, int s) {
    const auto map = horizontal_symmetry(s);
    BlockKey back = 0;
#pragma unroll
    for (int i = 0; i < 8; ++i) back |= ((key >> (3 * map[i])) & 7u) << (3 * i);
    return back;
  }
};

/// Threads per CUDA block of the dense kernel.
inline constexpr int kStepThreads = 256;

/// Consecutive blocks along x stepped by one thread (8 bytes of each of the group's 4 rows).
inline constexpr int kGroupBlocks = 4;
static_assert(kBrickBlocks % kGroupBlocks == 0, "a thread's group of blocks has a single owner brick");

/// The grid on the device: one byte per cell, x fastest, in a buffer of whole 8-byte words.
struct DeviceCells {
  std::uint8_t* cells = nullptr;  ///< the bytes
  Int3 size{};                    ///< grid extent
  std::uint8_t* side = nullptr;   ///< the side plane (momentum.hpp), laid out as the cells; null without one
};

/// Linear index offset of block cell i from the block's lowest corner.
__device__ inline std::int64_t block_cell_offset(int i, std::int64_t sy, std::int64_t sz) {
  return std::int64_t(i & 1) + sy * ((i >> 1) & 1) + sz * (i >> 2);
}

/// The 8 bytes of the grid buffer starting at byte `at` (any alignment), from the one or two
/// aligned words holding them; both lie inside the buffer since the 8 bytes do.
__device__ inline std::uint64_t load_bytes8(const std::uint8_t* cells, std::int64_t at) {
  const auto* word = reinterpret_cast<const std::uint64_t*>(cells + (at & ~std::int64_t(7)));
  const unsigned shift = unsigned(at & 7) * 8;
  const std::uint64_t low = word[0];
  return shift == 0 ? low : (low >> shift) | (word[1] << (64 - shift));
}

/// The Notes policy that records nothing.
struct NoNotes {
  /// Nothing to construct it from.
  struct Params {};
  __device__ NoNotes(const Params&, Int3) {}
  /// A stepped block.
  template <class Rule>
  __device__ void block(const Rule&, std::uint64_t, std::uint64_t) {}
  /// A stepped block holds a velocity (side plane): it is not quiet.
  __device__ void moving() {}
  /// Cell (x, y, z), inside the grid, changed.
  __device__ void changed(int, int, int) {}
  /// The thread is done.
  __device__ void flush() {}
};

/// Writes the bytes of `after` that differ from `before` to the block whose cell 0 is at linear
/// index `origin` and lowest corner (x0, y0, z0), where `inside` has bit i set (cells outside the
/// grid are never written), and notes each changed cell.
template <class Notes>
__device__ inline void store_block(const DeviceCells& g, std::int64_t origin, int x0, int y0, int z0,
                                   std::uint64_t before, std::uint64_t after, unsigned inside, Notes& notes) {
  const std::int64_t sy = g.size.x, sz = sy * g.size.y;
  const std::uint64_t diff = before ^ after;
#pragma unroll
  for (int i = 0; i < 8; ++i)
    if (((inside >> i) & 1u) != 0 && ((diff >> (8 * i)) & 0xFFu) != 0) {
      g.cells[origin + block_cell_offset(i, sy, sz)] = std::uint8_t(after >> (8 * i));
      notes.changed(x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + (i >> 2));
    }
}

/// True when the block's 8 bytes are equal and the Rule says such a block does not change.
template <class Rule>
__device__ inline bool skips_uniform(const Rule& rule, std::uint64_t bytes) {
  return bytes == (bytes & 0xFFu) * kEveryByte && !rule.steps_uniform(std::uint32_t(bytes & 0xFFu));
}

/// One block of a Rule that steps a side plane (Rule::kStepsSide), any position, as the CPU's row walk
/// steps it (cpu_block_row.hpp): its cells and side bytes gathered one by one (outside the grid they
/// read as rule.outside and 0 and are never written); a cell whose byte or side byte changed is
/// stored and noted, and a block left holding a velocity is not quiet. A uniform block the Rule
/// skips holds no liquid, so no velocity.
template <class Rule, class Notes>
__device__ inline void walk_side_block(const DeviceCells& g, const Rule& rule, int x0, int y0, int z0, Notes& notes) {
  const std::int64_t sy = g.size.x, sz = sy * g.size.y;
  const std::int64_t origin = std::int64_t(x0) + sy * y0 + sz * z0;
  std::uint64_t bytes = 0, side = 0;
  unsigned inside = 0;
#pragma unroll
  for (int i = 0; i < 8; ++i) {
    const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + (i >> 2);
    const bool in = x >= 0 && y >= 0 && z >= 0 && x < g.size.x && y < g.size.y && z < g.size.z;
    const std::int64_t at = origin + block_cell_offset(i, sy, sz);
    bytes |= std::uint64_t(in ? std::uint32_t(g.cells[at]) : rule.outside) << (8 * i);
    side |= std::uint64_t(in ? g.side[at] : 0u) << (8 * i);
    inside |= unsigned(in) << i;
  }
  if (skips_uniform(rule, bytes)) return;
  std::uint64_t side_after = side;
  const std::uint64_t after = rule.step(bytes, side_after, x0, y0, z0);
  notes.block(rule, bytes, after);
  if (side_after != 0) notes.moving();
  const std::uint64_t diff = bytes ^ after, side_diff = side ^ side_after;
  if ((diff | side_diff) == 0) return;
#pragma unroll
  for (int i = 0; i < 8; ++i) {
    if (((inside >> i) & 1u) == 0 || (((diff | side_diff) >> (8 * i)) & 0xFFu) == 0) continue;
    const std::int64_t at = origin + block_cell_offset(i, sy, sz);
    if (((diff >> (8 * i)) & 0xFFu) != 0) g.cells[at] = std::uint8_t(after >> (8 * i));
    if (((side_diff >> (8 * i)) & 0xFFu) != 0) g.side[at] = std::uint8_t(side_after >> (8 * i));
    notes.changed(x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + (i >> 2));
  }
}

/// One block, any position: cells outside the grid read as rule.outside and are never written (a
/// Rule that steps a side plane: walk_side_block). Its cells are gathered one by one; a Rule
/// without a motion model is stepped on the key itself (Rule::next_key), which spares an edge block
/// the byte packing the grouped path needs.
template <class Rule, class Notes>
__device__ inline void walk_edge_block(const DeviceCells& g, const Rule& rule, int x0, int y0, int z0, Notes& notes) {
  if constexpr (Rule::kStepsSide) {
    walk_side_block(g, rule, x0, y0, z0, notes);
    return;
  }
  const std::int64_t sy = g.size.x, sz = sy * g.size.y;
  const std::int64_t origin = std::int64_t(x0) + sy * y0 + sz * z0;
  std::uint64_t bytes = 0;
  BlockKey key = 0;
  unsigned inside = 0;
#pragma unroll
  for (int i = 0; i < 8; ++i) {
    const int x = x0 + (i & 1), y = y0 + ((i >> 1) & 1), z = z0 + (i >> 2);
    const bool in = x >= 0 && y >= 0 && z >= 0 && x < g.size.x && y < g.size.y && z < g.size.z;
    const std::uint32_t byte = in ? std::uint32_t(g.cells[origin + block_cell_offset(i, sy, sz)] & (Rule::kCellMask & 0xFFu))
                                  : rule.outside;
    inside |= unsigned(in) << i;
    if constexpr (Rule::kMotion)
      bytes |= std::uint64_t(byte) << (8 * i);
    else
      key |= byte << (3 * i);
  }
  if constexpr (Rule::kMotion) {
    if (skips_uniform(rule, bytes)) return;
    const std::uint64_t after = rule.step(bytes, x0, y0, z0);
    notes.block(rule, bytes, after);
    if (after != bytes) store_block(g, origin, x0, y0, z0, bytes, after, inside, notes);
  } else {
    if (key == (key & 7u) * 0x249249u) return;  // 8 equal states: every permutation is the identity
    const BlockKey next = rule.next_key(key, x0, y0, z0);
    if constexpr (!std::is_same_v<Notes, NoNotes>) notes.block(rule, unpack_key(key), unpack_key(next));
    if (next == key) return;
#pragma unroll
    for (int i = 0; i < 8; ++i) {
      const std::uint32_t value = (next >> (3 * i)) & 7u;
      if (((inside >> i) & 1u) != 0 && value != ((key >> (3 * i)) & 7u)) {
        g.cells[origin + block_cell_offset(i, sy, sz)] = std::uint8_t(value);
        notes.changed(x0 + (i & 1), y0 + ((i >> 1) & 1), z0 + (i >> 2));
      }
    }
  }
}

/// Steps the kGroupBlocks blocks starting at (x0, y0, z0) whose cells `row` holds: row r holds the
/// cells at (dy, dz) = (r & 1, r >> 1) of every block, 8 bytes per row (cells 2r and 2r + 1 of block
/// k in bytes 2k and 2k + 1). Calls moved(k, before, after) for each block k that changed. A group
/// of 32 equal bytes, or a block of 8, that the Rule does not step is skipped.
template <class Rule, class Notes, class Moved>
__device__ inline void step_group(const Rule& rule, const std::uint64_t (&row)[4], int x0, int y0, int z0, Notes& notes,
                                  Moved&& moved) {
  const std::uint64_t same = (row[0] & 0xFFu) * kEveryByte;
  if (((row[0] ^ same) | (row[1] ^ same) | (row[2] ^ same) | (row[3] ^ same)) == 0 &&
      !rule.steps_uniform(std::uint32_t(row[0] & 0xFFu)))
    return;
#pragma unroll
  for (int k = 0; k < kGroupBlocks; ++k) {
    std::uint64_t v = 0;
#pragma unroll
    for (int r = 0; r < 4; ++r) v |= ((row[r] >> (16 * k)) & 0xFFFFu) << (16 * r);
    if (skips_uniform(rule, v)) continue;
    const std::uint64_t after = rule.step(v, x0 + 2 * k, y0, z0);
    notes.block(rule, v, after);
    if (after != v) moved(k, v, after);
  }
}

/// kGroupBlocks blocks starting at (x0, y0, z0), all of whose cells lie inside the grid (a Rule that
/// steps a side plane: block by block, walk_side_block).
template <class Rule, class Notes>
__device__ inline void walk_inside_group(const DeviceCells& g, const Rule& rule, int x0, int y0, int z0, Notes& notes) {
  if constexpr (Rule::kStepsSide) {
    for (int k = 0; k < kGroupBlocks; ++k) walk_side_block(g, rule, x0 + 2 * k, y0, z0, notes);
    return;
  }
  const std::int64_t sy = g.size.x, sz = sy * g.size.y;
  const std::int64_t origin = std::int64_t(x0) + sy * y0 + sz * z0;
  std::uint64_t row[4];
#pragma unroll
  for (int r = 0; r < 4; ++r) row[r] = load_bytes8(g.cells, origin + sy * (r & 1) + sz * (r >> 1)) & Rule::kCellMask;
  step_group(rule, row, x0, y0, z0, notes, [&](int k, std::uint64_t before, std::uint64_t after) {
    store_block(g, origin + 2 * k, x0 + 2 * k, y0, z0, before, after, 0xFFu, notes);
  });
}

/// Flags brick of cell (x, y, z) in `changed` (per brick, x fastest, `bricks` per axis) unless it is
/// `owner`; returns true when it is (the caller collects that one).
__device__ inline bool flag_changed_cell(Int3 owner, Int3 bricks, std::uint8_t* changed, int x, int y, int z) {
  const int bx = brick_of(x), by = brick_of(y), bz = brick_of(z);
  if (bx == owner.x && by == owner.y && bz == owner.z) return true;
  changed[brick_index(bricks, bx, by, bz)] = 1;
  return false;
}

/// The owner brick of block `block` along an axis of `bricks` bricks (brick_grid.hpp's owned_blocks:
/// block k / kBrickBlocks, the last brick also owning the extra edge block).
__device__ inline int owner_brick(int block, int bricks) {
  const int b = block / kBrickBlocks;
  return b < bricks ? b : bricks - 1;
}

/// One (sub-)step over every block: thread (x, y) of CUDA block (bx, by, bz) takes the group of
/// kGroupBlocks blocks starting at block ((bx * blockDim.x + x) * kGroupBlocks, by * blockDim.y + y,
/// bz), so a warp reads 32 consecutive 8-byte segments of each of 4 rows. `np` builds each thread's
/// Notes (for the owner brick of its blocks).
template <class Rule, class Notes>
static __global__ void __launch_bounds__(kStepThreads)
    dense_kernel(DeviceCells g, Rule rule, typename Notes::Params np) {
  const BlockOffset o = rule.offset;
  const int first = int(blockIdx.x * blockDim.x + threadIdx.x) * kGroupBlocks;
  const int by = int(blockIdx.y * blockDim.y + threadIdx.y);
  const int bz = int(blockIdx.z);
  const int blocks_x = block_count(g.size.x, o.x);
  if (first >= blocks_x || by >= block_count(g.size.y, o.y) || bz >= block_count(g.size.z, o.z)) return;
  const int x0 = 2 * first - o.x, y0 = 2 * by - o.y, z0 = 2 * bz - o.z;
  Notes notes(np, Int3{first, by, bz});
  if (x0 >= 0 && x0 + 2 * kGroupBlocks <= g.size.x && y0 >= 0 && y0 + 1 < g.size.y && z0 >= 0 && z0 + 1 < g.size.z) {
    walk_inside_group(g, rule, x0, y0, z0, notes);
  } else {
    for (int k = 0; k < kGroupBlocks && first + k < blocks_x; ++k) walk_edge_block(g, rule, x0 + 2 * k, y0, z0, notes);
  }
  notes.flush();
}

/// Grid and block shape of the dense kernel for a grid of `size`, the same for all 8 offsets (the
/// largest block counts; threads past a step's counts return at once).
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

/// Builds the device Rule of step `n` of `rules` (block_step.hpp) and calls fn(rule) on the host,
/// which launches a kernel instantiated for its type.
template <class Fn>
inline void with_device_step(const StepRules& rules, std::uint64_t n, Fn&& fn) {
  with_step<DevicePlatform>(rules, n, fn);
}

/// Builds the device Rules of steps `n` and `n + 1` and calls fn(first, second) on the host.
template <class Fn>
inline void with_device_step_pair(const StepRules& rules, std::uint64_t n, Fn&& fn) {
  with_step_pair<DevicePlatform>(rules, n, fn);
}

/// Enqueues one (sub-)step of `rule` over every block on `stream`, with Notes built from `np`;
/// checks the launch (BackendError), not its completion.
template <class Notes, class Rule>
static inline void launch_dense(const DeviceCells& g, const Rule& rule, const StepShape& shape,
                                const typename Notes::Params& np, cudaStream_t stream) {
  dense_kernel<Rule, Notes><<<shape.grid, shape.block, 0, stream>>>(g, rule, np);
  check_launch("dense step kernel launch");
}

}  // namespace granular::cuda
