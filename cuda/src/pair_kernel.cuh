#pragma once
/// @file pair_kernel.cuh
/// Two steps in one pass over the grid, for every Rule (step/block_step.hpp): two consecutive ticks
/// t, t + 1 (t even) of a rule set without a motion model, or two consecutive sub-steps of the motion
/// model whose partitions share their x and y offsets. Shared by the CUDA backend and the CUDA
/// benchmark.
///
/// The two steps have the same x and y offsets and opposite z offsets, so during both every cell
/// stays inside its 2x2 column of the x/y partition: the first step pairs the layers (2k - o, 2k + 1
/// - o) (o its z offset), the second the layers in between. A thread takes kGroupBlocks adjacent
/// columns along x (8 bytes of each of 2 rows) over a chunk of layers [zs, ze) and walks it upwards
/// with a rolling window: it loads the two layers of the next first-step block (z, z + 1), applies
/// the first step to them, applies the second step to layers z - 1 (kept from the previous step of
/// the walk) and z, and stores the owned ones of those two layers, now final, where they changed.
/// The walk starts at z = zs - 2 + o; an owned cell after the second step needs cells up to 2 layers
/// below and 2 above the chunk (the halo).
///
/// The halo of one chunk is owned, and rewritten during the pass, by the neighbouring chunk, so
/// before the pass the 4 layers around every chunk boundary (zb - 2 .. zb + 1) are copied to a halo
/// buffer and every chunk reads its halo there. Cells outside the grid read as Rule::outside and are
/// never written, as in the dense kernel (block_walk.cuh), whose block arithmetic is used unchanged;
/// so the pair gives the same grid as two single steps.
///
/// With the OwnerNotes policy (dense-recording steps of sparse mode) the kernel also records, per
/// step, the flags the sparse kernel would set: each stepped block's quietness and the cells each
/// step changed (a cell changed by the first step and changed back by the second still counts, as
/// in two sparse steps). Each step has its own Notes, moved along z as the walk reaches the next
/// owner brick. The halo blocks a thread steps besides its own (the neighbouring chunk steps them
/// too, from the same cells) are recorded by both, with the same flags.

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <type_traits>

#include "block_walk.cuh"
#include "cuda_check.cuh"
#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"

namespace granular::cuda {

/// Tallest chunk of layers one thread of the pair kernel walks (even).
inline constexpr int kPairChunkMax = 64;

/// Shortest chunk (even): below it the halo (4 layers per chunk) costs more than it saves.
inline constexpr int kPairChunkMin = 16;

/// Threads the pair kernel aims for: the chunk height is halved (down to kPairChunkMin) until the
/// launch has at least this many, so small grids still fill the device.
inline constexpr std::int64_t kPairThreadsTarget = std::int64_t(1) << 19;

/// CUDA blocks per SM the plain pair kernel of the one-step rules without random symmetry is
/// compiled for (caps its registers at 64 per thread, which it fits without spilling).
inline constexpr int kPairMinBlocks = 4;

/// Grid and block shape of the pair kernel, with its split of the z axis into chunks.
struct PairShape {
  dim3 grid;       ///< CUDA blocks: (pieces of the column list, 1, chunks along z)
  dim3 block;      ///< threads: kStepThreads along x
  int chunk = 0;   ///< layers per chunk (even); the last chunk holds the rest, 2 .. chunk + 1 layers
  int chunks = 0;  ///< chunks along z
};

/// The pair kernel's shape for a grid of `size` with chunks of `chunk` layers (even, >= 4); 0
/// picks the height: kPairChunkMax, halved while the launch has fewer than kPairThreadsTarget
/// threads, but not below kPairChunkMin. Every chunk boundary zb has zb + 2 <= size.z.
inline PairShape pair_shape(Int3 size, int chunk = 0) {
  const std::int64_t groups = (block_count(size.x, 1) + kGroupBlocks - 1) / kGroupBlocks;
  const std::int64_t columns = groups * block_count(size.y, 1);
  if (chunk <= 0) {
    chunk = kPairChunkMax;
    while (chunk > kPairChunkMin && columns * ((size.z + chunk - 1) / chunk) < kPairThreadsTarget) chunk /= 2;
  }
  const int chunks = size.z >= 2 ? (size.z - 2) / chunk + 1 : 1;
  return {dim3(unsigned((columns + kStepThreads - 1) / kStepThreads), 1, unsigned(chunks)), dim3(kStepThreads, 1, 1),
          chunk, chunks};
}

/// Bytes of the halo buffer of `shape` on a grid of `size`: 4 layers per chunk boundary, plus one
/// word so that 8-byte reads of its last cells stay inside. 0 when there is a single chunk.
inline std::size_t pair_halo_bytes(Int3 size, const PairShape& shape) {
  if (shape.chunks <= 1) return 0;
  const std::size_t layer = std::size_t(size.x) * std::size_t(size.y);
  return (std::size_t(shape.chunks - 1) * 4 * layer + 15) / 8 * 8;
}

/// CUDA blocks per SM a pair kernel is compiled for: kPairMinBlocks for the plain one-step rules
/// without random symmetry (they fit its register cap), else 1 (the random symmetry, the motion model
/// and the recording state would spill under it).
template <class Rule, class Notes>
constexpr int pair_min_blocks() {
  return std::is_same_v<Notes, NoNotes> && std::is_same_v<Rule, OneStepRule<false, DevicePlatform>> ? kPairMinBlocks : 1;
}

/// One step of `rule` on the kGroupBlocks blocks of two layers held in `row`: row r holds the cells
/// at (dy, dz) = (r & 1, r >> 1) of the blocks starting at (x0 + 2k, y0, z0), 8 bytes per row; cells
/// outside the grid hold rule.outside and keep it (a transition never moves a static cell).
template <class Rule, class Notes>
__device__ inline void step_pair_layers(const Rule& rule, std::uint64_t (&row)[4], int x0, int y0, int z0,
                                        Notes& notes) {
  step_group(rule, row, x0, y0, z0, notes, [&](int k, std::uint64_t, std::uint64_t moved) {
#pragma unroll
    for (int r = 0; r < 4; ++r)
      row[r] = (row[r] & ~(0xFFFFull << (16 * k))) | (((moved >> (16 * r)) & 0xFFFFu) << (16 * k));
  });
}

/// Stores the bytes of `after` that differ from `before` at byte `at` of the grid (any alignment),
/// in naturally aligned pieces of 1, 2, 4 or 8 bytes, so no byte outside the 8 is written.
__device__ inline void store_changed8(std::uint8_t* cells, std::int64_t at, std::uint64_t before, std::uint64_t after) {
  const std::uint64_t diff = before ^ after;
  if (diff == 0) return;
  int done = 0;
  while (done < 8) {
    const std::int64_t a = at + done;
    int piece = 8;
    while (piece > 8 - done || (a & (piece - 1)) != 0) piece /= 2;
    const std::uint64_t mask = piece == 8 ? ~0ull : ((1ull << (8 * piece)) - 1);
    const std::uint64_t value = (after >> (8 * done)) & mask;
    if (((diff >> (8 * done)) & mask) != 0) {
      switch (piece) {
        case 8: *reinterpret_cast<std::uint64_t*>(cells + a) = value; break;
        case 4: *reinterpret_cast<std::uint32_t*>(cells + a) = std::uint32_t(value); break;
        case 2: *reinterpret_cast<std::uint16_t*>(cells + a) = std::uint16_t(value); break;
        default: cells[a] = std::uint8_t(value); break;
      }
    }
    done += piece;
  }
}

/// Where one thread of the pair kernel reads and writes: its 8-byte x range in 2 rows of every
/// layer, in the grid or the halo buffer.
struct PairColumn {
  std::uint8_t* cells;  ///< the grid
  Int3 size;            ///< grid extent
  const std::uint8_t* halo;  ///< the halo buffer (4 layers per chunk boundary)
  std::int64_t sy, sz;  ///< row and layer strides
  int x0, y0;           ///< lowest corner of the thread's first block
  int zs, ze;           ///< owned layers [zs, ze)
  int chunk_index;      ///< the thread's chunk along z
  bool x_inside;        ///< all 8 x positions inside the grid
  bool row_inside[2];   ///< rows y0 and y0 + 1 inside the grid
  std::uint64_t mask;     ///< Rule::kCellMask
  std::uint64_t outside;  ///< Rule::outside in every byte

  /// The buffer holding layer z (the grid or the halo buffer, both 8-byte aligned) and the layer's
  /// first byte in it; nullptr outside the grid.
  __device__ const std::uint8_t* layer(int z, std::int64_t& start) const {
    if (z < 0 || z >= size.z) return nullptr;
    if (z < zs) {
      start = sz * (std::int64_t(chunk_index - 1) * 4 + (z - zs + 2));
      return halo;
    }
    if (z >= ze) {
      start = sz * (std::int64_t(chunk_index) * 4 + 2 + (z - ze));
      return halo;
    }
    start = sz * z;
    return cells;
  }

  /// The thread's 8 cells of row dy of layer z, each masked; those outside the grid read as outside.
  __device__ std::uint64_t load(int z, int dy) const {
    std::int64_t start = 0;
    const std::uint8_t* buffer = layer(z, start);
    if (buffer == nullptr || !row_inside[dy]) return outside;
    const std::int64_t at = start + sy * (y0 + dy) + x0;
    if (x_inside) return load_bytes8(buffer, at) & mask;
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) {
      const int x = x0 + i;
      const std::uint64_t cell = x >= 0 && x < size.x ? (buffer[at + i] & mask & 0xFFu) : (outside & 0xFFu);
      v |= cell << (8 * i);
    }
    return v;
  }

  /// Writes the changed cells of row dy of owned layer z.
  __device__ void store(int z, int dy, std::uint64_t before, std::uint64_t after) const {
    if (!row_inside[dy] || before == after) return;
    const std::int64_t at = sz * z + sy * (y0 + dy) + x0;
    if (x_inside) {
      store_changed8(cells, at, before, after);
      return;
    }
    for (int i = 0; i < 8; ++i) {
      const int x = x0 + i;
      const std::uint8_t value = std::uint8_t(after >> (8 * i));
      if (x >= 0 && x < size.x && value != std::uint8_t(before >> (8 * i))) cells[at + i] = value;
    }
  }
};

/// Records the rows of `after` that differ from `before`: row q at (y0 + (q & 1), z + (q >> 1)).
template <class Notes>
__device__ inline void note_changed_rows(Notes& notes, const std::uint64_t (&before)[4], const std::uint64_t (&after)[4],
                                         int x0, int y0, int z) {
  if constexpr (!std::is_same_v<Notes, NoNotes>) {
#pragma unroll
    for (int q = 0; q < 4; ++q)
      if (after[q] != before[q]) notes.changed_row(after[q] ^ before[q], x0, y0 + (q & 1), z + (q >> 1));
  }
}

/// Steps `first` then `second` (same x and y offsets, opposite z offsets): thread x of CUDA block
/// (bx, 0, bz) takes entry i = bx * blockDim.x + x of the list of column groups (kGroupBlocks
/// columns along x, x fastest, then y: consecutive threads read consecutive bytes of a row and no
/// thread idles at a row's end) over chunk bz of `chunk` layers, reading its halo from `halo` (see
/// the file comment).
template <class Rule, class Notes>
static __global__ void __launch_bounds__(kStepThreads, pair_min_blocks<Rule, Notes>())
    pair_kernel(DeviceCells g, Rule first, Rule second, const std::uint8_t* halo, int chunk, int chunks,
                typename Notes::Params np) {
  const BlockOffset o = first.offset;
  const unsigned groups = unsigned(block_count(g.size.x, o.x) + kGroupBlocks - 1) / kGroupBlocks;
  const unsigned entry = blockIdx.x * blockDim.x + threadIdx.x;
  const int group = int(entry % groups) * kGroupBlocks;
  const int by = int(entry / groups);
  if (by >= block_count(g.size.y, o.y)) return;
  PairColumn c;
  c.cells = g.cells;
  c.size = g.size;
  c.halo = halo;
  c.sy = g.size.x;
  c.sz = c.sy * g.size.y;
  c.x0 = 2 * group - o.x;
  c.y0 = 2 * by - o.y;
  c.chunk_index = int(blockIdx.z);
  c.zs = c.chunk_index * chunk;
  c.ze = c.chunk_index + 1 == chunks ? g.size.z : c.zs + chunk;
  c.x_inside = c.x0 >= 0 && c.x0 + 8 <= g.size.x;
  c.row_inside[0] = c.y0 >= 0;
  c.row_inside[1] = c.y0 + 1 < g.size.y;
  c.mask = Rule::kCellMask;
  c.outside = kEveryByte * first.outside;
  // Each step's notes start at the walk's first block along z.
  const int z_first = c.zs - 2 + o.z;
  Notes notes_first(np, Int3{group, by, (z_first > 0 ? z_first + o.z : 0) / 2});
  Notes notes_second(np, Int3{group, by, (z_first > 0 ? z_first - o.z : 0) / 2});

  // Layer z - 1 from the previous step of the walk: after the first step, and as loaded.
  std::uint64_t kept_after[2] = {c.outside, c.outside}, kept_before[2] = {c.outside, c.outside};
  // The next two layers are loaded one step ahead, so their loads overlap this step's work.
  std::uint64_t ahead[4];
#pragma unroll
  for (int r = 0; r < 4; ++r) ahead[r] = c.load(z_first + (r >> 1), r & 1);
  for (int z = z_first; z <= c.ze; z += 2) {
    std::uint64_t before[4], row[4];
#pragma unroll
    for (int r = 0; r < 4; ++r) row[r] = before[r] = ahead[r];
    if (z + 2 <= c.ze) {
#pragma unroll
      for (int r = 0; r < 4; ++r) ahead[r] = c.load(z + 2 + (r >> 1), r & 1);
    }
    if constexpr (!std::is_same_v<Notes, NoNotes>) notes_first.set_owner_z((z > 0 ? z + o.z : 0) / 2);
    step_pair_layers(first, row, c.x0, c.y0, z, notes_first);
    note_changed_rows(notes_first, before, row, c.x0, c.y0, z);
    if (z >= c.zs) {
      const std::uint64_t after_first[4] = {kept_after[0], kept_after[1], row[0], row[1]};
      std::uint64_t second_rows[4] = {kept_after[0], kept_after[1], row[0], row[1]};
      if constexpr (!std::is_same_v<Notes, NoNotes>) notes_second.set_owner_z((z - 1 > 0 ? z - o.z : 0) / 2);
      step_pair_layers(second, second_rows, c.x0, c.y0, z - 1, notes_second);
      note_changed_rows(notes_second, after_first, second_rows, c.x0, c.y0, z - 1);
      if (z - 1 >= c.zs) {
        c.store(z - 1, 0, kept_before[0], second_rows[0]);
        c.store(z - 1, 1, kept_before[1], second_rows[1]);
      }
      if (z < c.ze) {
        c.store(z, 0, before[0], second_rows[2]);
        c.store(z, 1, before[1], second_rows[3]);
      }
    }
    kept_after[0] = row[2];
    kept_after[1] = row[3];
    kept_before[0] = before[2];
    kept_before[1] = before[3];
  }
  notes_first.flush();
  notes_second.flush();
}

/// Copies layers zb - 2 .. zb + 1 around every chunk boundary zb = b * chunk (b = 1 .. boundaries)
/// to slot b - 1 of `halo`: 8-byte words when a layer is whole words, else bytes.
static __global__ void halo_copy_kernel(const std::uint8_t* cells, std::uint8_t* halo, std::int64_t layer, int chunk,
                                        int boundaries) {
  const std::int64_t slot = 4 * layer;
  const std::int64_t stride = std::int64_t(gridDim.x) * blockDim.x;
  const std::int64_t first = std::int64_t(blockIdx.x) * blockDim.x + threadIdx.x;
  if (layer % 8 == 0) {
    const std::int64_t words = slot / 8;
    for (std::int64_t i = first; i < words * boundaries; i += stride) {
      const std::int64_t b = i / words, w = i % words;
      const std::int64_t from = ((b + 1) * chunk - 2) * layer / 8 + w;
      reinterpret_cast<std::uint64_t*>(halo)[b * words + w] = reinterpret_cast<const std::uint64_t*>(cells)[from];
    }
    return;
  }
  for (std::int64_t i = first; i < slot * boundaries; i += stride) {
    const std::int64_t b = i / slot, at = i % slot;
    halo[i] = cells[((b + 1) * chunk - 2) * layer + at];
  }
}

/// True when `first` and `second` may run as one pair: the same x and y offsets and the first
/// step's z offset the opposite of the second's.
inline bool pairable(const BlockOffset& first, const BlockOffset& second) {
  return first.x == second.x && first.y == second.y && first.z != second.z;
}

/// Enqueues `first` then `second` (pairable) on `stream`: copies the layers around each chunk
/// boundary of `shape` to `halo` (pair_halo_bytes(size, shape) bytes; may be null when that is 0),
/// then runs the pair kernel with Notes built from `np`. Checks the launches (BackendError), not
/// their completion.
template <class Notes, class Rule>
static inline void launch_pair(const DeviceCells& g, const Rule& first, const Rule& second, const PairShape& shape,
                               std::uint8_t* halo, const typename Notes::Params& np, cudaStream_t stream) {
  if (shape.chunks > 1) {
    const std::int64_t layer = std::int64_t(g.size.x) * g.size.y;
    const std::int64_t work = 4 * layer * (shape.chunks - 1) / (layer % 8 == 0 ? 8 : 1);
    const unsigned blocks = unsigned(std::min<std::int64_t>((work + kStepThreads - 1) / kStepThreads, 4096));
    halo_copy_kernel<<<blocks, kStepThreads, 0, stream>>>(g.cells, halo, layer, shape.chunk, shape.chunks - 1);
    check_launch("pair halo copy launch");
  }
  pair_kernel<Rule, Notes><<<shape.grid, shape.block, 0, stream>>>(g, first, second, halo, shape.chunk, shape.chunks, np);
  check_launch("step pair kernel launch");
}

}  // namespace granular::cuda
