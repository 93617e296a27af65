#pragma once
/// @file step_pair_kernel.cuh
/// Two ticks (an even tick t and t + 1) in one pass over the grid. Shared by the CUDA backend and
/// the CUDA benchmark.
///
/// Ticks t and t + 1 (t even) have the same x and y offsets and differ only in z, so during both
/// ticks every cell stays inside its 2x2 column of the x/y partition: tick t pairs the layers
/// (2k, 2k + 1), tick t + 1 the layers (2k - 1, 2k). A thread takes kGroupBlocks adjacent columns
/// along x (8 bytes of each of 2 rows) over a chunk of layers [zs, ze) and walks it upwards with a
/// rolling window: it loads layers 2j and 2j + 1, applies tick t to them, applies tick t + 1 to
/// layers 2j - 1 (kept from the previous step) and 2j, and stores the owned ones of those two
/// layers, now final, where they changed. Cell zs after t + 1 needs cells zs - 1 and zs after t,
/// which need layers zs - 2 .. zs + 1; symmetrically at the top: a chunk reads 2 layers below and 2
/// above the layers it owns (the halo).
///
/// The halo of one chunk is owned, and rewritten during the pass, by the neighbouring chunk, so
/// before the pass the 4 layers around every chunk boundary (zb - 2 .. zb + 1) are copied to a
/// halo buffer and every chunk reads its halo there. Cells outside the grid read as solid and are
/// never written, exactly as in the single-tick kernel (step_kernel.cuh), whose block arithmetic,
/// result table and random draw (per block: its own origin and tick) are used unchanged; so the
/// pair gives the same grid as two single ticks.
///
/// The recording form (step_pair_record_kernel, for dense-recording ticks of sparse mode) also
/// records, per tick, the flags the sparse step kernel would set (activity_record.cuh): each
/// stepped block's key, and the cells each tick changed (a cell changed by tick t and changed back
/// by t + 1 still counts, as in two sparse ticks). Both blocks of one step of the walk (tick t at
/// layers z, z + 1; tick t + 1 at z - 1, z) have block index z / 2 along z, hence the same owner
/// brick; a thread stores its owner's flags when the walk reaches the next owner along z. The halo
/// blocks a thread steps besides its own (the neighbouring chunk steps them too, from the same
/// cells) are recorded by both, with the same flags.

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>

#include "activity_record.cuh"
#include "cuda_check.cuh"
#include "granular/block.hpp"
#include "granular/geometry.hpp"
#include "step_kernel.cuh"

namespace granular::cuda {

/// Tallest chunk of layers one thread of the pair kernel walks (even).
inline constexpr int kPairChunkMax = 64;

/// Shortest chunk (even): below it the halo (4 layers per chunk) costs more than it saves.
inline constexpr int kPairChunkMin = 16;

/// Threads the pair kernel aims for: the chunk height is halved (down to kPairChunkMin) until the
/// launch has at least this many, so small grids still fill the device.
inline constexpr std::int64_t kPairThreadsTarget = std::int64_t(1) << 19;

/// CUDA blocks per SM the pair kernel without random symmetry is compiled for (caps its registers
/// at 64 per thread, which it fits without spilling; the random-symmetry variant would spill).
inline constexpr int kPairMinBlocks = 4;

/// Eight cells of the state kOutsideCell, one per byte.
inline constexpr std::uint64_t kOutsideRow = 0x0101010101010101ull * kOutsideCell;

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

/// Spreads a key's 8 3-bit states to bytes 0..7 (cell i in byte i): the inverse of pack_block_bytes.
__device__ inline std::uint64_t unpack_block_bytes(BlockKey key) {
  std::uint64_t t = key;
  t = (t | (t << 20)) & 0x00000FFF00000FFFull;
  t = (t | (t << 10)) & 0x003F003F003F003Full;
  return (t | (t << 5)) & 0x0707070707070707ull;
}

/// One tick on the kGroupBlocks blocks of two layers held in `row`: row r holds the cells at
/// (dy, dz) = (r & 1, r >> 1) of the blocks starting at (x0 + 2k, y0, z0), 8 bytes per row; cells
/// outside the grid hold kOutsideCell and keep it (a transition never moves a solid cell). With
/// kRecord, notes the keys of the stepped blocks in `*f` (inert table of `*rec`).
template <bool kRandom, bool kRecord = false>
__device__ inline void step_pair_layers(const StepParams& p, std::uint64_t tick, std::uint64_t (&row)[4], int x0,
                                        int y0, int z0, const ActivityRecord* rec = nullptr, OwnerFlags* f = nullptr) {
  constexpr std::uint64_t kEveryByte = 0x0101010101010101ull;
  const std::uint64_t same = (row[0] & 0xFFu) * kEveryByte;
  if (((row[0] ^ same) | (row[1] ^ same) | (row[2] ^ same) | (row[3] ^ same)) == 0) return;
#pragma unroll
  for (int k = 0; k < kGroupBlocks; ++k) {
    std::uint64_t v = 0;
#pragma unroll
    for (int r = 0; r < 4; ++r) v |= ((row[r] >> (16 * k)) & 0xFFFFu) << (16 * r);
    if (v == (v & 0xFFu) * kEveryByte) continue;
    const BlockKey key = pack_block_bytes(v);
    const BlockKey next = next_key_at<kRandom>(p, tick, key, x0 + 2 * k, y0, z0);
    if constexpr (kRecord) record_key<kRandom>(*rec, *f, key, next);
    if (next == key) continue;
    const std::uint64_t moved = unpack_block_bytes(next);
#pragma unroll
    for (int r = 0; r < 4; ++r)
      row[r] = (row[r] & ~(0xFFFFull << (16 * k))) | (((moved >> (16 * r)) & 0xFFFFu) << (16 * k));
  }
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

  /// The thread's 8 cells of row dy of layer z, each masked to its 3 bits; outside ones solid.
  __device__ std::uint64_t load(int z, int dy) const {
    std::int64_t start = 0;
    const std::uint8_t* buffer = layer(z, start);
    if (buffer == nullptr || !row_inside[dy]) return kOutsideRow;
    const std::int64_t at = start + sy * (y0 + dy) + x0;
    if (x_inside) return load_bytes8(buffer, at) & (7 * (kOutsideRow / kOutsideCell));
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) {
      const int x = x0 + i;
      const std::uint64_t cell = x >= 0 && x < size.x ? (buffer[at + i] & 7u) : kOutsideCell;
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

/// Ticks p.tick (even) and p.tick + 1: thread x of CUDA block (bx, 0, bz) takes entry
/// i = bx * blockDim.x + x of the tick's list of column groups (kGroupBlocks columns along x, x
/// fastest, then y: consecutive threads read consecutive bytes of a row and no thread idles at a
/// row's end) over chunk bz of `chunk` layers, reading its halo from `halo` (see the file comment).
template <bool kRandom>
static __global__ void __launch_bounds__(kStepThreads, kRandom ? 1 : kPairMinBlocks)
    step_pair_kernel(StepParams p, const std::uint8_t* halo, int chunk, int chunks) {
  const BlockOffset o = block_offset(p.tick, p.seed, p.random_axis_order);
  const unsigned groups = unsigned(block_count(p.size.x, o.x) + kGroupBlocks - 1) / kGroupBlocks;
  const unsigned entry = blockIdx.x * blockDim.x + threadIdx.x;
  const int first = int(entry % groups) * kGroupBlocks;
  const int by = int(entry / groups);
  if (by >= block_count(p.size.y, o.y)) return;
  PairColumn c;
  c.cells = p.cells;
  c.size = p.size;
  c.halo = halo;
  c.sy = p.size.x;
  c.sz = c.sy * p.size.y;
  c.x0 = 2 * first - o.x;
  c.y0 = 2 * by - o.y;
  c.chunk_index = int(blockIdx.z);
  c.zs = c.chunk_index * chunk;
  c.ze = c.chunk_index + 1 == chunks ? p.size.z : c.zs + chunk;
  c.x_inside = c.x0 >= 0 && c.x0 + 8 <= p.size.x;
  c.row_inside[0] = c.y0 >= 0;
  c.row_inside[1] = c.y0 + 1 < p.size.y;

  // Layer 2j - 1 from the previous step: after tick t, and as loaded.
  std::uint64_t kept_after[2] = {kOutsideRow, kOutsideRow}, kept_before[2] = {kOutsideRow, kOutsideRow};
  // The next two layers are loaded one step ahead, so their loads overlap this step's work.
  std::uint64_t ahead[4];
#pragma unroll
  for (int r = 0; r < 4; ++r) ahead[r] = c.load(c.zs - 2 + (r >> 1), r & 1);
  for (int z = c.zs - 2; z <= c.ze; z += 2) {
    std::uint64_t before[4], row[4];
#pragma unroll
    for (int r = 0; r < 4; ++r) row[r] = before[r] = ahead[r];
    if (z + 2 <= c.ze) {
#pragma unroll
      for (int r = 0; r < 4; ++r) ahead[r] = c.load(z + 2 + (r >> 1), r & 1);
    }
    step_pair_layers<kRandom>(p, p.tick, row, c.x0, c.y0, z);
    if (z >= c.zs) {
      std::uint64_t second[4] = {kept_after[0], kept_after[1], row[0], row[1]};
      step_pair_layers<kRandom>(p, p.tick + 1, second, c.x0, c.y0, z - 1);
      if (z - 1 >= c.zs) {
        c.store(z - 1, 0, kept_before[0], second[0]);
        c.store(z - 1, 1, kept_before[1], second[1]);
      }
      if (z < c.ze) {
        c.store(z, 0, before[0], second[2]);
        c.store(z, 1, before[1], second[3]);
      }
    }
    kept_after[0] = row[2];
    kept_after[1] = row[3];
    kept_before[0] = before[2];
    kept_before[1] = before[3];
  }
}

/// step_pair_kernel recording the sparse flags of both ticks in `rec` (activity_record.cuh and the
/// file comment): the same walk through the kRecord form of step_pair_layers, plus each tick's
/// changed rows. (A body shared with step_pair_kernel, inlined into both, changes
/// step_pair_kernel's machine code; the plain kernel keeps its own.) Compiled without the plain
/// kernel's register cap, under which the recording state would spill.
template <bool kRandom>
static __global__ void __launch_bounds__(kStepThreads, 1)
    step_pair_record_kernel(StepParams p, const std::uint8_t* halo, int chunk, int chunks, ActivityRecord rec) {
  const BlockOffset o = block_offset(p.tick, p.seed, p.random_axis_order);
  const unsigned groups = unsigned(block_count(p.size.x, o.x) + kGroupBlocks - 1) / kGroupBlocks;
  const unsigned entry = blockIdx.x * blockDim.x + threadIdx.x;
  const int first = int(entry % groups) * kGroupBlocks;
  const int by = int(entry / groups);
  if (by >= block_count(p.size.y, o.y)) return;
  PairColumn c;
  c.cells = p.cells;
  c.size = p.size;
  c.halo = halo;
  c.sy = p.size.x;
  c.sz = c.sy * p.size.y;
  c.x0 = 2 * first - o.x;
  c.y0 = 2 * by - o.y;
  c.chunk_index = int(blockIdx.z);
  c.zs = c.chunk_index * chunk;
  c.ze = c.chunk_index + 1 == chunks ? p.size.z : c.zs + chunk;
  c.x_inside = c.x0 >= 0 && c.x0 + 8 <= p.size.x;
  c.row_inside[0] = c.y0 >= 0;
  c.row_inside[1] = c.y0 + 1 < p.size.y;
  OwnerFlags f;
  f.owner = {owner_brick(first, rec.bricks.x), owner_brick(by, rec.bricks.y), -1};

  // Layer 2j - 1 from the previous step: after tick t, and as loaded.
  std::uint64_t kept_after[2] = {kOutsideRow, kOutsideRow}, kept_before[2] = {kOutsideRow, kOutsideRow};
  // The next two layers are loaded one step ahead, so their loads overlap this step's work.
  std::uint64_t ahead[4];
#pragma unroll
  for (int r = 0; r < 4; ++r) ahead[r] = c.load(c.zs - 2 + (r >> 1), r & 1);
  for (int z = c.zs - 2; z <= c.ze; z += 2) {
    std::uint64_t before[4], row[4];
#pragma unroll
    for (int r = 0; r < 4; ++r) row[r] = before[r] = ahead[r];
    if (z + 2 <= c.ze) {
#pragma unroll
      for (int r = 0; r < 4; ++r) ahead[r] = c.load(z + 2 + (r >> 1), r & 1);
    }
    // Both blocks of this step (tick t at z, tick t + 1 at z - 1) have block index z / 2 along z.
    const int owner_z = owner_brick((z > 0 ? z : 0) / 2, rec.bricks.z);
    if (owner_z != f.owner.z) {
      flush_owner(rec, f);
      f.owner.z = owner_z;
      f.non_inert = f.owner_changed = false;
    }
    step_pair_layers<kRandom, true>(p, p.tick, row, c.x0, c.y0, z, &rec, &f);
#pragma unroll
    for (int q = 0; q < 4; ++q)
      if (row[q] != before[q]) record_changed_row(rec, f, row[q] ^ before[q], c.x0, c.y0 + (q & 1), z + (q >> 1));
    if (z >= c.zs) {
      const std::uint64_t after_first[4] = {kept_after[0], kept_after[1], row[0], row[1]};
      std::uint64_t second[4] = {kept_after[0], kept_after[1], row[0], row[1]};
      step_pair_layers<kRandom, true>(p, p.tick + 1, second, c.x0, c.y0, z - 1, &rec, &f);
#pragma unroll
      for (int q = 0; q < 4; ++q)
        if (second[q] != after_first[q])
          record_changed_row(rec, f, second[q] ^ after_first[q], c.x0, c.y0 + (q & 1), z - 1 + (q >> 1));
      if (z - 1 >= c.zs) {
        c.store(z - 1, 0, kept_before[0], second[0]);
        c.store(z - 1, 1, kept_before[1], second[1]);
      }
      if (z < c.ze) {
        c.store(z, 0, before[0], second[2]);
        c.store(z, 1, before[1], second[3]);
      }
    }
    kept_after[0] = row[2];
    kept_after[1] = row[3];
    kept_before[0] = before[2];
    kept_before[1] = before[3];
  }
  flush_owner(rec, f);
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

/// Enqueues ticks p.tick (even) and p.tick + 1 on `stream`: copies the layers around each chunk
/// boundary of `shape` to `halo` (pair_halo_bytes(p.size, shape) bytes; may be null when that is 0),
/// then runs the pair kernel, recording the sparse flags in `*record` when given. Checks the
/// launches (BackendError), not their completion.
static inline void launch_step_pair(const StepParams& p, bool random_symmetry, const PairShape& shape,
                                    std::uint8_t* halo, cudaStream_t stream, const ActivityRecord* record = nullptr) {
  if (shape.chunks > 1) {
    const std::int64_t layer = std::int64_t(p.size.x) * p.size.y;
    const std::int64_t work = 4 * layer * (shape.chunks - 1) / (layer % 8 == 0 ? 8 : 1);
    const unsigned blocks = unsigned(std::min<std::int64_t>((work + kStepThreads - 1) / kStepThreads, 4096));
    halo_copy_kernel<<<blocks, kStepThreads, 0, stream>>>(p.cells, halo, layer, shape.chunk, shape.chunks - 1);
    check_launch("pair halo copy launch");
  }
  if (record != nullptr) {
    if (random_symmetry)
      step_pair_record_kernel<true><<<shape.grid, shape.block, 0, stream>>>(p, halo, shape.chunk, shape.chunks, *record);
    else
      step_pair_record_kernel<false><<<shape.grid, shape.block, 0, stream>>>(p, halo, shape.chunk, shape.chunks, *record);
    check_launch("step pair record kernel launch");
    return;
  }
  if (random_symmetry)
    step_pair_kernel<true><<<shape.grid, shape.block, 0, stream>>>(p, halo, shape.chunk, shape.chunks);
  else
    step_pair_kernel<false><<<shape.grid, shape.block, 0, stream>>>(p, halo, shape.chunk, shape.chunks);
  check_launch("step pair kernel launch");
}

}  // namespace granular::cuda
