#pragma once
/// @file box_transfer.cuh
/// Copies of a box of cells between the device grid and packed host memory (x fastest), through a
/// staging buffer the backend keeps and reuses: page-locked host memory mapped into the device's
/// address space, which a kernel reads or writes directly (no copy call). A box is cut into chunks
/// of at most kTransferChunkBytes cells; one kernel gathers (or scatters) each chunk between the
/// grid and the staging. Reading a chunk waits for the device once; writing one waits for nothing
/// but the staging being free of the last write. Many small boxes (Backend::read_boxes and
/// write_boxes) move as one batch: a table of their chunks, then their cells, in the staging, and
/// one kernel whose block rows each copy one chunk; where the caller's cells lie in the backend's
/// transfer buffer (Backend::transfer_buffer, mapped as the staging is), the kernel copies them
/// there in place and the staging holds the table only.

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cuda_check.cuh"
#include "granular/errors.hpp"
#include "granular/geometry.hpp"

namespace granular::cuda {

/// Cells one chunk of a box transfer holds at most, unless one row of the box is longer.
inline constexpr std::uint64_t kTransferChunkBytes = std::uint64_t(4) << 20;

/// One chunk of a box: a sub-box of whole rows, and where its cells start in the box's packed bytes.
struct BoxChunk {
  Int3 min{};                ///< first cell, grid coordinates
  Int3 extent{};             ///< cells per axis
  std::uint64_t offset = 0;  ///< index of its first cell in the box's packed bytes
  /// Cells in the chunk.
  std::uint64_t cells() const { return std::uint64_t(extent.x) * std::uint64_t(extent.y) * std::uint64_t(extent.z); }
};

/// Calls fn(chunk) for the chunks of the non-empty `box` in packed order, each of at most `limit`
/// cells or one row: runs of whole z slices of the box while a slice fits, else runs of rows of one slice.
template <class Fn>
void for_each_chunk(const Box& box, std::uint64_t limit, Fn&& fn) {
  const Int3 e = box.extent();
  const std::uint64_t row = std::uint64_t(e.x), slice = row * std::uint64_t(e.y);
  if (slice <= limit) {
    const int slices = int(std::min<std::uint64_t>(std::uint64_t(e.z), limit / slice));
    for (int z = 0; z < e.z; z += slices)
      fn(BoxChunk{{box.min.x, box.min.y, box.min.z + z}, {e.x, e.y, std::min(slices, e.z - z)},
                  slice * std::uint64_t(z)});
    return;
  }
  const int rows = int(std::max<std::uint64_t>(1, limit / row));
  for (int z = 0; z < e.z; ++z)
    for (int y = 0; y < e.y; y += rows)
      fn(BoxChunk{{box.min.x, box.min.y + y, box.min.z + z}, {e.x, std::min(rows, e.y - y), 1},
                  slice * std::uint64_t(z) + row * std::uint64_t(y)});
}

/// A chunk as the gather and scatter kernels take it.
struct ChunkCopy {
  std::uint8_t* cells = nullptr;    ///< the grid
  std::uint64_t pitch_y = 0;        ///< bytes from one grid row to the next (size.x)
  std::uint64_t pitch_z = 0;        ///< bytes from one grid slice to the next (size.x * size.y)
  std::uint64_t origin = 0;         ///< grid index of the chunk's first cell
  unsigned width = 0, height = 0;   ///< the chunk's extent along x and y
  unsigned count = 0;               ///< cells in the chunk
  std::uint8_t* packed = nullptr;   ///< the chunk's cells, x fastest: the staging's device address
  std::uint8_t* side = nullptr;     ///< the grid's side plane, or null: a scattered cell that changes
                                    ///< gets side byte 0 (a new cell, at rest)
};

/// Grid index of the i-th cell (x fastest) of chunk `c`.
__device__ inline std::uint64_t chunk_cell(const ChunkCopy& c, unsigned i) {
  const unsigned x = i % c.width, r = i / c.width, y = r % c.height, z = r / c.height;
  return c.origin + std::uint64_t(x) + c.pitch_y * y + c.pitch_z * z;
}

/// packed[i] = the chunk's i-th cell, for the i this thread strides over along x of the launch.
__device__ inline void gather_cells(const ChunkCopy& c) {
  for (unsigned i = blockIdx.x * blockDim.x + threadIdx.x; i < c.count; i += gridDim.x * blockDim.x)
    c.packed[i] = c.cells[chunk_cell(c, i)];
}

/// The chunk's i-th cell = packed[i], for the i this thread strides over along x of the launch; with
/// a side plane, a cell that changes loses its velocity.
__device__ inline void scatter_cells(const ChunkCopy& c) {
  for (unsigned i = blockIdx.x * blockDim.x + threadIdx.x; i < c.count; i += gridDim.x * blockDim.x) {
    const std::uint64_t at = chunk_cell(c, i);
    const std::uint8_t value = c.packed[i];
    if (c.side != nullptr && c.cells[at] != value) c.side[at] = 0;
    c.cells[at] = value;
  }
}

/// Gathers one chunk into its packed bytes.
__global__ void gather_chunk_kernel(ChunkCopy c) { gather_cells(c); }

/// Scatters one chunk's packed bytes into the grid.
__global__ void scatter_chunk_kernel(ChunkCopy c) { scatter_cells(c); }

/// Gathers chunk copies[blockIdx.y] of a batch (Backend::read_boxes: many boxes, one launch).
__global__ void gather_chunks_kernel(const ChunkCopy* copies) { gather_cells(copies[blockIdx.y]); }

/// Scatters chunk copies[blockIdx.y] of a batch (Backend::write_boxes). Boxes of a batch that
/// overlap carry the same bytes there, so the order the blocks run in does not matter.
__global__ void scatter_chunks_kernel(const ChunkCopy* copies) { scatter_cells(copies[blockIdx.y]); }

/// The most chunks one batch launch holds (its grid's y extent).
inline constexpr std::size_t kMaxBatchChunks = 65535;

/// Calls fn(chunks, bytes) for batches of the chunks of `boxes` (packed one after the other, each
/// chunk's offset counted from the first box's first cell), each batch holding at most
/// kTransferChunkBytes cells (or one chunk) and kMaxBatchChunks chunks; `bytes` is the cells of the batch.
template <class Fn>
void for_each_batch(std::span<const Box> boxes, Fn&& fn) {
  std::vector<BoxChunk> batch;
  std::uint64_t bytes = 0, box_offset = 0;
  for (const Box& box : boxes) {
    for_each_chunk(box, kTransferChunkBytes, [&](BoxChunk chunk) {
      if (!batch.empty() && (bytes + chunk.cells() > kTransferChunkBytes || batch.size() == kMaxBatchChunks)) {
        fn(std::span<const BoxChunk>(batch), bytes);
        batch.clear();
        bytes = 0;
      }
      chunk.offset += box_offset;
      batch.push_back(chunk);
      bytes += chunk.cells();
    });
    box_offset += std::uint64_t(box.volume());
  }
  if (!batch.empty()) fn(std::span<const BoxChunk>(batch), bytes);
}

/// Bytes of the table of `chunks` chunk copies at the start of a batch's staging (16-byte aligned).
inline std::uint64_t batch_table_bytes(std::size_t chunks) { return (chunks * sizeof(ChunkCopy) + 15) / 16 * 16; }

/// Threads per block of the chunk kernels.
inline constexpr unsigned kChunkThreads = 256;

/// Blocks of the chunk kernels for `count` cells (the kernels loop over the rest).
inline unsigned chunk_blocks(unsigned count) { return std::max(1u, std::min((count + kChunkThreads - 1) / kChunkThreads, 8192u)); }

/// The copy of `chunk` of a grid of `size` cells at `cells`, packed at `packed`.
inline ChunkCopy chunk_copy(std::uint8_t* cells, Int3 size, const BoxChunk& chunk, std::uint8_t* packed) {
  ChunkCopy c;
  c.cells = cells;
  c.pitch_y = std::uint64_t(size.x);
  c.pitch_z = c.pitch_y * std::uint64_t(size.y);
  c.origin = std::uint64_t(chunk.min.x) + c.pitch_y * std::uint64_t(chunk.min.y) + c.pitch_z * std::uint64_t(chunk.min.z);
  c.width = unsigned(chunk.extent.x);
  c.height = unsigned(chunk.extent.y);
  c.count = unsigned(chunk.cells());
  c.packed = packed;
  return c;
}

/// Frees page-locked host memory.
struct PinnedBytesFree {
  /// cudaFreeHost, ignoring null.
  void operator()(std::uint8_t* p) const noexcept {
    if (p != nullptr) cudaFreeHost(p);
  }
};

/// The staging of box transfers: page-locked host memory mapped into the device's address space.
/// It grows to the largest transfer asked for (at most a chunk and a wake list) and is reused; an
/// event tells when the device has finished the last kernel that reads it.
class TransferStaging {
 public:
  TransferStaging() = default;
  ~TransferStaging() {
    // An enqueued kernel may still read the staging: let it finish before freeing it.
    if (event_ != nullptr) {
      cudaEventSynchronize(event_);
      cudaEventDestroy(event_);
    }
  }
  TransferStaging(const TransferStaging&) = delete;
  TransferStaging& operator=(const TransferStaging&) = delete;

  /// Makes the staging hold at least `bytes`; when it must grow, first waits for `stream`, whose
  /// enqueued kernels may still use it. Throws OutOfMemory or BackendError.
  void reserve(std::uint64_t bytes, cudaStream_t stream) {
    if (event_ == nullptr) check(cudaEventCreateWithFlags(&event_, cudaEventDisableTiming), "cudaEventCreate (staging)");
    if (bytes <= capacity_) return;
    check(cudaStreamSynchronize(stream), "waiting for the device before growing the transfer staging");
    free_ = true;
    std::uint64_t capacity = std::max<std::uint64_t>(capacity_, kMinimumBytes);
    while (capacity < bytes) capacity *= 2;
    host_.reset();
    device_ = nullptr;
    capacity_ = 0;
    void* host = nullptr;
    const cudaError_t status = cudaHostAlloc(&host, capacity, cudaHostAllocMapped);
    if (status == cudaErrorMemoryAllocation) {
      cudaGetLastError();
      throw OutOfMemory("cuda backend: could not allocate " + std::to_string(capacity) +
                        " bytes of page-locked host memory for the transfer staging");
    }
    check(status, "cudaHostAlloc (transfer staging)");
    host_.reset(static_cast<std::uint8_t*>(host));
    void* device = nullptr;
    check(cudaHostGetDevicePointer(&device, host, 0), "cudaHostGetDevicePointer (transfer staging)");
    device_ = static_cast<std::uint8_t*>(device);
    capacity_ = capacity;
  }
  /// Bytes it holds.
  std::uint64_t capacity() const { return capacity_; }
  /// The staging's host address (reserve first).
  std::uint8_t* host() const { return host_.get(); }
  /// The staging's device address, for kernels (reserve first).
  std::uint8_t* device() const { return device_; }
  /// Waits until the device has finished the last kernel that reads the staging (read_until); at
  /// once, with no call to the driver, when it is known to have (mark_free).
  void wait_free() {
    if (free_) return;
    check(cudaEventSynchronize(event_), "waiting for the transfer staging");
    free_ = true;
  }
  /// Marks the staging busy until the device reaches this point of `stream` (after the kernels
  /// that read it).
  void read_until(cudaStream_t stream) {
    check(cudaEventRecord(event_, stream), "cudaEventRecord (staging)");
    free_ = false;
  }
  /// Tells the staging that the device has finished every kernel enqueued so far (the caller has
  /// just synchronised the stream of its kernels), so that the next wait_free need not ask.
  void mark_free() { free_ = true; }

 private:
  static constexpr std::uint64_t kMinimumBytes = std::uint64_t(64) << 10;  ///< a tool's box and wake list fit
  std::unique_ptr<std::uint8_t, PinnedBytesFree> host_;
  std::uint8_t* device_ = nullptr;
  std::uint64_t capacity_ = 0;
  cudaEvent_t event_ = nullptr;
  bool free_ = true;  ///< the device has finished every kernel that reads the staging (wait_free need not ask)
};

}  // namespace granular::cuda
