#pragma once
/// @file activity_record.cuh
/// What the dense and pair kernels record in their recording form (dense-recording steps of sparse
/// mode, docs/design/sparse-stepping.md): the per-brick flags the sparse kernel sets for
/// the bricks it steps. `dirty[owner]` when a stepped block is not quiet (Rule::quiet), and
/// `changed[brick of the cell]` for every cell a step changes.
///
/// A thread of the dense kernel steps kGroupBlocks consecutive blocks along x starting at a multiple
/// of kGroupBlocks, so all of them have the same owner brick (kBrickBlocks is a multiple of
/// kGroupBlocks): the thread collects the flags of that owner in registers (OwnerNotes) and stores
/// each at most once; only a changed cell of another brick (a block straddling a brick boundary)
/// is stored at once.

#include <cuda_runtime.h>

#include <cstdint>

#include "block_walk.cuh"
#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"
#include "step/brick_grid.hpp"

namespace granular::cuda {

/// The per-brick flags the recording kernels set (the sparse state's dirty and changed bytes).
struct ActivityRecord {
  Int3 bricks{};                  ///< bricks per axis
  std::uint8_t* dirty = nullptr;    ///< per brick: a block it owns was not quiet
  std::uint8_t* changed = nullptr;  ///< per brick: one of its cells changed
};

/// The Notes policy of the recording kernels: one thread's flags for its current owner brick.
struct OwnerNotes {
  /// What it is built from.
  using Params = ActivityRecord;

  /// The notes of a thread whose blocks have block indices `block` (the first of its group).
  __device__ OwnerNotes(const ActivityRecord& record, Int3 block)
      : r(record),
        owner{owner_brick(block.x, record.bricks.x), owner_brick(block.y, record.bricks.y),
              owner_brick(block.z, record.bricks.z)} {
    read_dirty();
  }

  /// A stepped block that is not quiet marks the owner dirty (an owner already dirty in this cycle
  /// needs no quiet test: the flag only ever turns on until the cycle's end).
  template <class Rule>
  __device__ void block(const Rule& rule, std::uint64_t before, std::uint64_t after) {
    if (!non_inert && !rule.quiet(before, after)) non_inert = true;
  }

  /// A stepped block holds a velocity (side plane): it is not quiet.
  __device__ void moving() { non_inert = true; }

  /// Starts the owner's flags from its dirty byte.
  __device__ void read_dirty() {
    was_dirty = r.dirty[brick_index(r.bricks, owner.x, owner.y, owner.z)] != 0;
    non_inert = was_dirty;
  }

  /// Records that cell (x, y, z), inside the grid, changed: collected when it is in the owner brick,
  /// else flagged at once.
  __device__ void changed(int x, int y, int z) {
    if (flag_changed_cell(owner, r.bricks, r.changed, x, y, z)) owner_changed = true;
  }

  /// Records the changed cells of an 8-cell row piece starting at (x0, y, z): `diff` has a non-zero
  /// byte i where cell (x0 + i, y, z) changed (only cells inside the grid change). 8 consecutive
  /// cells span at most two bricks along x, those of the lowest and of the highest changed cell.
  __device__ void changed_row(std::uint64_t diff, int x0, int y, int z) {
    const int low = x0 + ((__ffsll(static_cast<long long>(diff)) - 1) >> 3);
    const int high = x0 + ((63 - __clzll(static_cast<long long>(diff))) >> 3);
    changed(low, y, z);
    if (brick_of(high) != brick_of(low)) changed(high, y, z);
  }

  /// Stores the collected flags of the owner brick (nothing when none is set) and forgets them.
  __device__ void flush() {
    const bool dirty = non_inert && !was_dirty;
    if (!dirty && !owner_changed) return;
    const std::uint32_t index = brick_index(r.bricks, owner.x, owner.y, owner.z);
    if (dirty) r.dirty[index] = 1;
    if (owner_changed) r.changed[index] = 1;
    was_dirty = was_dirty || non_inert;
    owner_changed = false;
  }

  /// The following blocks have owner brick `z` along z (block index `block_z`): flushes on a change.
  __device__ void set_owner_z(int block_z) {
    const int z = owner_brick(block_z, r.bricks.z);
    if (z == owner.z) return;
    flush();
    owner.z = z;
    read_dirty();
  }

  ActivityRecord r;            ///< where the flags go
  Int3 owner{};                ///< the owner brick's coordinates
  bool non_inert = false;      ///< a block it owns was not quiet (or it was dirty already)
  bool was_dirty = false;      ///< the owner's dirty byte was set when this thread looked
  bool owner_changed = false;  ///< a cell of the owner brick itself changed
};

}  // namespace granular::cuda
