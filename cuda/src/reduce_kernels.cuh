#pragma once
/// @file reduce_kernels.cuh
/// Whole-grid reductions on the device: the grid hash's word sum (hash_cells in grid.hpp, over
/// whole bytes; a side plane's too), whether a side plane holds a velocity, and the per-material
/// histogram (over each byte's material bits: a motion rule set's motion level is not a material,
/// granular/motion.hpp). All read the bytes as 8-byte little-endian words; the buffer is allocated
/// in whole words, and bytes past the last cell are masked, whatever they hold.
/// Kernels and launchers here are static: every translation unit including this gets its own copy.

#include <cuda_runtime.h>

#include <cstdint>

#include "cuda_check.cuh"
#include "granular/grid.hpp"
#include "granular/material.hpp"
#include "granular/motion.hpp"

namespace granular::cuda {

/// Threads per CUDA block of the reduction kernels.
inline constexpr int kReduceThreads = 256;

/// The constant of hash_words (grid.cpp): word i is mixed with (i + 1) times it.
inline constexpr std::uint64_t kHashGolden = 0x9E3779B97F4A7C15ull;

/// Word `i` of the cells (n cells in all), bytes at or past n replaced by `fill` bytes.
__device__ inline std::uint64_t cell_word(const std::uint8_t* cells, std::uint64_t n, std::uint64_t i,
                                          std::uint64_t fill) {
  std::uint64_t w = reinterpret_cast<const std::uint64_t*>(cells)[i];
  const std::uint64_t at = i * 8;
  if (at + 8 > n) {
    const std::uint64_t keep = (std::uint64_t(1) << (8 * (n - at))) - 1;  // n - at is 1..7
    w = (w & keep) | (fill & ~keep);
  }
  return w;
}

/// Word `i` of the cells' materials (n cells in all): each byte & kMaterialMask, bytes at or past
/// n 0xFF (no material).
__device__ inline std::uint64_t material_word(const std::uint8_t* cells, std::uint64_t n, std::uint64_t i) {
  constexpr std::uint64_t kMaterialBytes = 0x0101010101010101ull * kMaterialMask;
  const std::uint64_t at = i * 8;
  const std::uint64_t keep = at + 8 > n ? (std::uint64_t(1) << (8 * (n - at))) - 1 : ~std::uint64_t(0);
  return (reinterpret_cast<const std::uint64_t*>(cells)[i] & kMaterialBytes & keep) | ~keep;
}

/// Sum of a value over the CUDA block's threads; the result is valid in thread 0.
__device__ inline unsigned long long block_sum(unsigned long long v) {
  __shared__ unsigned long long warp_sums[kReduceThreads / 32];
  for (int d = 16; d > 0; d /= 2) v += __shfl_down_sync(0xFFFFFFFFu, v, d);
  const int lane = int(threadIdx.x) % 32, warp = int(threadIdx.x) / 32;
  __syncthreads();
  if (lane == 0) warp_sums[warp] = v;
  __syncthreads();
  if (warp == 0) {
    v = lane < kReduceThreads / 32 ? warp_sums[lane] : 0;
    for (int d = 16; d > 0; d /= 2) v += __shfl_down_sync(0xFFFFFFFFu, v, d);
  }
  return v;
}

/// Adds sum over words i of mix64(w_i + (i + 1) * kHashGolden) into *sum (mod 2^64; the tail word
/// zero-padded as in hash_words). Launch with kReduceThreads threads per CUDA block, any grid.
static __global__ void __launch_bounds__(kReduceThreads) hash_kernel(const std::uint8_t* cells, std::uint64_t n,
                                                               unsigned long long* sum) {
  const std::uint64_t words = (n + 7) / 8;
  std::uint64_t local = 0;
  for (std::uint64_t i = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; i < words;
       i += std::uint64_t(gridDim.x) * blockDim.x)
    local += mix64(cell_word(cells, n, i, 0) + (i + 1) * kHashGolden);
  const unsigned long long total = block_sum(local);
  if (threadIdx.x == 0) atomicAdd(sum, total);
}

/// Sets *flag to 1 when a byte of the n bytes is not 0 (a side plane that holds a velocity).
static __global__ void __launch_bounds__(kReduceThreads) nonzero_kernel(const std::uint8_t* bytes, std::uint64_t n,
                                                                  unsigned* flag) {
  const std::uint64_t words = (n + 7) / 8;
  bool any = false;
  for (std::uint64_t i = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; i < words && !any;
       i += std::uint64_t(gridDim.x) * blockDim.x)
    any = cell_word(bytes, n, i, 0) != 0;
  if (any) *flag = 1u;
}

/// Adds the number of cells holding each material 0..7 (a byte's low bits) into counts[0..7].
/// Launch with kReduceThreads threads per CUDA block.
static __global__ void __launch_bounds__(kReduceThreads) count_kernel(const std::uint8_t* cells, std::uint64_t n,
                                                                unsigned long long* counts) {
  const std::uint64_t words = (n + 7) / 8;
  unsigned long long local[kMaterialCount] = {};
  for (std::uint64_t i = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; i < words;
       i += std::uint64_t(gridDim.x) * blockDim.x) {
    const std::uint64_t w = material_word(cells, n, i);
    const unsigned lo = unsigned(w), hi = unsigned(w >> 32);
#pragma unroll
    for (int m = 0; m < kMaterialCount; ++m) {
      const unsigned pattern = 0x01010101u * unsigned(m);
      local[m] += unsigned(__popc(__vcmpeq4(lo, pattern)) + __popc(__vcmpeq4(hi, pattern))) / 8u;
    }
  }
#pragma unroll
  for (int m = 0; m < kMaterialCount; ++m) {
    const unsigned long long total = block_sum(local[m]);
    if (threadIdx.x == 0 && total != 0) atomicAdd(counts + m, total);
  }
}

/// CUDA blocks for a grid-stride reduction over the words of `n` cells: enough to fill the
/// device (`sm_count` multiprocessors) several times over, never more than there are words.
inline unsigned reduce_blocks(std::uint64_t n, int sm_count) {
  const std::uint64_t words = (n + 7) / 8;
  const std::uint64_t needed = (words + kReduceThreads - 1) / kReduceThreads;
  const std::uint64_t cap = std::uint64_t(sm_count > 0 ? sm_count : 1) * 8;
  return unsigned(needed < cap ? (needed > 0 ? needed : 1) : cap);
}

}  // namespace granular::cuda
