#pragma once
/// @file activity_record.cuh
/// What the dense kernels record in their recording form (dense-recording ticks of sparse mode,
/// docs/ARCHITECTURE.md, "Activity tracking"): the same per-brick flags the sparse step kernel
/// sets for the bricks it steps. `dirty[owner]` when a stepped block's key is non-inert (the inert
/// table with random symmetry, `next != key` otherwise: sparse_step_kernel.cuh's note_key), and
/// `changed[brick of the cell]` for every cell a tick changes (its note_changed_cell).
///
/// A thread of the dense kernels steps kGroupBlocks consecutive blocks along x starting at a
/// multiple of kGroupBlocks, so all of them have the same owner brick (kBrickBlocks is a multiple
/// of kGroupBlocks): the thread collects the flags of that owner in registers (OwnerFlags) and
/// stores each at most once; only a changed cell of another brick (a block straddling a brick
/// boundary) is stored at once.

#include <cuda_runtime.h>

#include <cstdint>

#include "step/brick_grid.hpp"
#include "granular/block.hpp"
#include "granular/geometry.hpp"

namespace granular::cuda {

/// The per-brick flags the recording kernels set (the sparse state's dirty and changed bytes).
struct ActivityRecord {
  Int3 bricks{};                         ///< bricks per axis
  std::uint8_t* dirty = nullptr;         ///< per brick: a block it owns had a non-inert key
  std::uint8_t* changed = nullptr;       ///< per brick: one of its cells changed
  const std::uint64_t* inert = nullptr;  ///< inert-key bits (with random symmetry; else unused)
};

/// The brick owning block `block` along an axis of `bricks` bricks (brick_grid.hpp's owned_blocks:
/// block k / kBrickBlocks, the last brick also owning the extra edge block).
__device__ inline int owner_brick(int block, int bricks) {
  const int b = block / kBrickBlocks;
  return b < bricks ? b : bricks - 1;
}

/// One thread's flags for its current owner brick, stored by flush_owner.
struct OwnerFlags {
  Int3 owner{};                ///< the owner brick's coordinates
  bool non_inert = false;      ///< a block it owns had a non-inert key
  bool owner_changed = false;  ///< a cell of the owner brick itself changed
};

/// Notes a stepped block's key (`next` its key after the tick): sparse_step_kernel.cuh's note_key.
template <bool kRandom>
__device__ inline void record_key(const ActivityRecord& r, OwnerFlags& f, BlockKey key, BlockKey next) {
  if constexpr (kRandom) {
    if (!f.non_inert && ((__ldg(r.inert + (key >> 6)) >> (key & 63u)) & 1u) == 0) f.non_inert = true;
  } else {
    f.non_inert |= next != key;
  }
}

/// Records that cell (x, y, z), inside the grid, changed: collected when it is in the owner brick,
/// else flagged at once.
__device__ inline void record_changed_cell(const ActivityRecord& r, OwnerFlags& f, int x, int y, int z) {
  const int bx = brick_of(x), by = brick_of(y), bz = brick_of(z);
  if (bx == f.owner.x && by == f.owner.y && bz == f.owner.z)
    f.owner_changed = true;
  else
    r.changed[brick_index(r.bricks, bx, by, bz)] = 1;
}

/// Records the changed cells of an 8-cell row piece starting at (x0, y, z): `diff` has a non-zero
/// byte i where cell (x0 + i, y, z) changed (only cells inside the grid change). 8 consecutive
/// cells span at most two bricks along x, those of the lowest and of the highest changed cell.
__device__ inline void record_changed_row(const ActivityRecord& r, OwnerFlags& f, std::uint64_t diff, int x0, int y,
                                          int z) {
  const int low = x0 + ((__ffsll(static_cast<long long>(diff)) - 1) >> 3);
  const int high = x0 + ((63 - __clzll(static_cast<long long>(diff))) >> 3);
  record_changed_cell(r, f, low, y, z);
  if (brick_of(high) != brick_of(low)) record_changed_cell(r, f, high, y, z);
}

/// Stores the collected flags of the owner brick (nothing when none is set).
__device__ inline void flush_owner(const ActivityRecord& r, const OwnerFlags& f) {
  if (!f.non_inert && !f.owner_changed) return;
  const std::uint32_t index = brick_index(r.bricks, f.owner.x, f.owner.y, f.owner.z);
  if (f.non_inert) r.dirty[index] = 1;
  if (f.owner_changed) r.changed[index] = 1;
}

}  // namespace granular::cuda
