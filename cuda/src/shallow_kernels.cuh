#pragma once
/// @file shallow_kernels.cuh
/// The kernels of MotionParams::shallow: the shallow-water pass after the last sub-step of a tick
/// (granular/step/shallow_water.hpp), as the CPU backend runs it (cpu_shallow_pass.cpp): one thread
/// per column or face calls the shared functions, each step of an iteration one launch, so every
/// step reads what the step before it wrote on every column, and the four move phases touch
/// disjoint column pairs. The cells and the face plane are the CPU's bit for bit.

#include <cuda_runtime.h>

#include <cstddef>
#include <cstdint>

#include "cuda_check.cuh"
#include "granular/geometry.hpp"
#include "sparse_kernel.cuh"
#include "step/brick_grid.hpp"
#include "step/shallow_water.hpp"
#include "step/step_materials.hpp"

namespace granular::cuda {

/// Threads per CUDA block of the shallow-water kernels.
inline constexpr int kShallowThreads = 256;

/// The device grid as move_face reads and writes it, noting each column's changed cells.
struct DeviceShallowGrid {
  std::uint8_t* cells;  ///< the grid's cells
  std::size_t layer;    ///< cells per layer
  std::int32_t* lo;     ///< per column: the lowest cell a move changed this pass
  std::int32_t* hi;     ///< per column: the highest
  /// The cell at z of `column`.
  constexpr std::uint8_t get(std::int64_t column, int z) const { return cells[std::size_t(column) + std::size_t(z) * layer]; }
  /// Writes the cell at z of `column` and notes it (one thread owns a column within a launch).
  constexpr void set(std::int64_t column, int z, std::uint8_t byte) const {
    cells[std::size_t(column) + std::size_t(z) * layer] = byte;
    if (z < lo[column]) lo[column] = z;
    if (z > hi[column]) hi[column] = z;
  }
};

/// The columns of the grid (shallow::ColumnScan), one thread per column walking it bottom up.
static __global__ void shallow_scan_kernel(const std::uint8_t* cells, Int3 size, StepMaterials m, shallow::Plane p) {
  const std::uint64_t columns = std::uint64_t(size.x) * std::uint64_t(size.y);
  for (std::uint64_t c = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; c < columns;
       c += std::uint64_t(gridDim.x) * blockDim.x) {
    shallow::ColumnScan scan;
    for (int z = 0; z < size.z; ++z) scan.visit(z, cells[c + std::uint64_t(z) * columns], m);
    p.columns[c] = scan.result();
  }
}

/// The flags of a pass on the device: whether the current iteration changed a face or a cell,
/// whether the pass did, whether an iteration changed nothing, after which the rest of the tick's
/// iterations would change nothing either and the kernels return at once, and whether the grid has
/// a covered column (else the heads' step returns at once).
struct ShallowFlags {
  unsigned iteration;  ///< the current iteration changed something
  unsigned pass;       ///< the pass changed something
  unsigned done;       ///< an iteration changed nothing: the pass is over
  unsigned covered;    ///< a column is covered (its room is under a static cell) this tick
};

/// shallow::settle_column on every column, one thread per column, after the scan, and the first
/// iteration's surface_of (which reads the column's own settled column only); notes a covered column
/// in flags->covered.
static __global__ void shallow_settle_kernel(shallow::Plane p, ShallowFlags* flags) {
  const std::uint64_t columns = std::uint64_t(p.nx) * std::uint64_t(p.ny);
  for (std::uint64_t c = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; c < columns;
       c += std::uint64_t(gridDim.x) * blockDim.x) {
    const int x = int(c % std::uint64_t(p.nx)), y = int(c / std::uint64_t(p.nx));
    shallow::settle_column(p.columns, p.nx, p.ny, x, y);
    if (p.columns[c].covered() && flags->covered == 0) flags->covered = 1;  // every writer stores the same value
    shallow::surface_of(p, x, y);
  }
}

/// One step of an iteration over every column (whose surfaces the launch before computed): 0 head_of
/// (with a covered column), 1 update_face (both axes), 2 limit_column, 3 split_face (both axes; a
/// change of a face sets flags->iteration).
static __global__ void shallow_step_kernel(shallow::Plane p, int step, ShallowFlags* flags) {
  if (flags->done != 0 || (step == 0 && flags->covered == 0)) return;
  const std::uint64_t columns = std::uint64_t(p.nx) * std::uint64_t(p.ny);
  for (std::uint64_t c = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; c < columns;
       c += std::uint64_t(gridDim.x) * blockDim.x) {
    const int x = int(c % std::uint64_t(p.nx)), y = int(c / std::uint64_t(p.nx));
    if (step == 0) {
      shallow::head_of(p, x, y);
    } else if (step == 1) {
      for (int a = 0; a < shallow::kAxes; ++a) shallow::update_face(p, x, y, a);
    } else if (step == 2) {
      shallow::limit_column(p, x, y);
    } else {
      bool any = false;
      for (int a = 0; a < shallow::kAxes; ++a) {
        const std::int32_t u = p.u[a][c], f = p.fraction[a][c];
        shallow::split_face(p, x, y, a);
        any = any || u != p.u[a][c] || f != p.fraction[a][c] || p.cells[a][c] != 0;
      }
      if (any && flags->iteration == 0) flags->iteration = 1;  // every writer stores the same value
    }
  }
}

/// The moves of phase `phase` (shallow::in_phase), one thread per face of the phase.
static __global__ void shallow_move_kernel(shallow::Plane p, DeviceShallowGrid grid, StepMaterials m, int phase,
                                           const ShallowFlags* flags) {
  if (flags->done != 0) return;
  const int axis = shallow::phase_axis(phase);
  // The phase's faces: every other column along its axis.
  const int along = axis == 0 ? (p.nx - phase % 2 + 1) / 2 : (p.ny - phase % 2 + 1) / 2;
  const std::uint64_t faces = std::uint64_t(along) * std::uint64_t(axis == 0 ? p.ny : p.nx);
  for (std::uint64_t i = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; i < faces;
       i += std::uint64_t(gridDim.x) * blockDim.x) {
    int x, y;
    if (axis == 0) {
      x = 2 * int(i % std::uint64_t(along)) + phase % 2;
      y = int(i / std::uint64_t(along));
    } else {
      x = int(i % std::uint64_t(p.nx));
      y = 2 * int(i / std::uint64_t(p.nx)) + phase % 2;
    }
    shallow::move_face(p, grid, x, y, axis, m);
  }
}

/// The end of an iteration and the surfaces of the next: the first thread ends the pass after an
/// iteration that changed nothing (else counts it for the pass) and clears the iteration's flag;
/// every thread computes surface_of for its columns (unused after the pass's last iteration).
static __global__ void shallow_iteration_end_kernel(shallow::Plane p, ShallowFlags* flags) {
  if (blockIdx.x == 0 && threadIdx.x == 0 && flags->done == 0) {
    if (flags->iteration == 0) flags->done = 1;
    else flags->pass = 1;
    flags->iteration = 0;
  }
  const std::uint64_t columns = std::uint64_t(p.nx) * std::uint64_t(p.ny);
  for (std::uint64_t c = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; c < columns;
       c += std::uint64_t(gridDim.x) * blockDim.x)
    shallow::surface_of(p, int(c % std::uint64_t(p.nx)), int(c / std::uint64_t(p.nx)));
}

/// The bricks of the cells the pass changed: flagged in `flags` and in the sparse state's
/// `changed` (with `sparse`), and each column's record cleared for the next pass.
static __global__ void shallow_changed_kernel(Int3 size, DeviceShallowGrid grid, bool sparse, SparseParams s,
                                              std::uint8_t* flags) {
  const std::uint64_t columns = std::uint64_t(size.x) * std::uint64_t(size.y);
  for (std::uint64_t c = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; c < columns;
       c += std::uint64_t(gridDim.x) * blockDim.x) {
    const int lo = grid.lo[c], hi = grid.hi[c];
    if (lo > hi) continue;
    grid.lo[c] = size.z;
    grid.hi[c] = -1;
    if (!sparse) continue;
    const int bx = brick_of(int(c % std::uint64_t(size.x))), by = brick_of(int(c / std::uint64_t(size.x)));
    for (int bz = brick_of(lo); bz <= brick_of(hi); ++bz) {
      const std::uint32_t b = brick_index(s.bricks, bx, by, bz);
      if (flags[b] == 0) flags[b] = 1;  // every writer stores the same byte
      if (s.changed[b] == 0) s.changed[b] = 1;
    }
  }
}

/// Blocks of kShallowThreads for `count` items, at most 65,535 (the kernels stride).
inline unsigned shallow_blocks(std::uint64_t count) {
  const std::uint64_t blocks = (count + kShallowThreads - 1) / kShallowThreads;
  return unsigned(blocks < 65535 ? (blocks > 0 ? blocks : 1) : 65535);
}

}  // namespace granular::cuda
