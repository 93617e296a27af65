#pragma once
/// @file pinned_counters.cuh
/// A few 64-bit counters in page-locked host memory: the target of an asynchronous copy from the
/// device that the host reads only after synchronising (a copy to pageable memory would block).

#include <cuda_runtime.h>

#include <cstddef>
#include <cstring>
#include <memory>

#include "cuda_check.cuh"

namespace granular::cuda {

/// Frees page-locked host memory.
struct PinnedFree {
  /// cudaFreeHost, ignoring null.
  void operator()(unsigned long long* p) const noexcept {
    if (p != nullptr) cudaFreeHost(p);
  }
};

/// Counters in page-locked host memory, freed by the owner.
using PinnedCounters = std::unique_ptr<unsigned long long[], PinnedFree>;

/// `count` zeroed counters in page-locked host memory. Throws BackendError when CUDA cannot
/// allocate them.
inline PinnedCounters pinned_counters(std::size_t count) {
  void* memory = nullptr;
  check(cudaMallocHost(&memory, count * sizeof(unsigned long long)), "cudaMallocHost (activity counters)");
  std::memset(memory, 0, count * sizeof(unsigned long long));
  return PinnedCounters(static_cast<unsigned long long*>(memory));
}

}  // namespace granular::cuda
