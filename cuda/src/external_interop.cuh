#pragma once
/// @file external_interop.cuh
/// Memory and timeline semaphores exported by a graphics API (opaque POSIX fds), imported into
/// CUDA: the cell buffer a renderer reads without a copy, and the semaphores that order the
/// simulation's writes with the renderer's reads.

#include <cuda_runtime.h>

#include <cstdint>
#include <string>

#include "cuda_check.cuh"
#include "granular/errors.hpp"
#include "granular/external_memory.hpp"
#include "owned_handle.cuh"

namespace granular::cuda {

/// An imported allocation with `bytes` of it mapped as a device buffer; unmapped and released by
/// its destructor. Move-only.
class ImportedMemory {
 public:
  /// Imports `memory` and maps `bytes` from its offset. On success CUDA owns memory.fd; on failure
  /// (BackendError naming the CUDA error) the fd is still the caller's.
  ImportedMemory(const ExternalCellMemory& memory, std::uint64_t bytes)
      : external_(import_memory(memory)), data_(map_buffer(external_.get(), memory.offset, bytes)) {}

  /// The mapped device pointer.
  std::uint8_t* data() const { return data_.get(); }

 private:
  using Memory = OwnedHandle<cudaExternalMemory_t, cudaDestroyExternalMemory>;
  static Memory import_memory(const ExternalCellMemory& memory) {
    cudaExternalMemoryHandleDesc handle{};
    handle.type = cudaExternalMemoryHandleTypeOpaqueFd;
    handle.handle.fd = memory.fd;
    handle.size = memory.allocation_size;
    handle.flags = memory.dedicated ? cudaExternalMemoryDedicated : 0u;
    return create_owned<cudaExternalMemory_t, cudaDestroyExternalMemory>(
        [&](cudaExternalMemory_t* external) { return cudaImportExternalMemory(external, &handle); },
        "cudaImportExternalMemory (shared cell buffer)");
  }
  static std::uint8_t* map_buffer(cudaExternalMemory_t external, std::uint64_t offset, std::uint64_t bytes) {
    cudaExternalMemoryBufferDesc buffer{};
    buffer.offset = offset;
    buffer.size = bytes;
    void* mapped = nullptr;
    check(cudaExternalMemoryGetMappedBuffer(&mapped, external, &buffer),
          "cudaExternalMemoryGetMappedBuffer (shared cell buffer)");
    return static_cast<std::uint8_t*>(mapped);
  }
  // Declared in this order so that the mapping is freed before the memory is released; when the
  // mapping fails, the imported memory is released as the constructor throws.
  Memory external_;
  OwnedHandle<std::uint8_t*, cudaFree> data_;
};

/// An imported timeline semaphore. Move-only.
class ImportedTimeline {
 public:
  /// Imports `timeline`. On success CUDA owns timeline.fd; BackendError otherwise.
  ImportedTimeline(const ExternalTimeline& timeline, const char* what)
      : semaphore_(import_semaphore(timeline, what)) {}

  /// Makes work enqueued on `stream` after this wait until the semaphore reaches `value`.
  void wait(std::uint64_t value, cudaStream_t stream) const {
    const cudaExternalSemaphore_t semaphore = semaphore_.get();
    cudaExternalSemaphoreWaitParams params{};
    params.params.fence.value = value;
    check(cudaWaitExternalSemaphoresAsync(&semaphore, &params, 1, stream), "cudaWaitExternalSemaphoresAsync");
  }
  /// Sets the semaphore to `value` once the work enqueued on `stream` so far is done.
  void signal(std::uint64_t value, cudaStream_t stream) const {
    const cudaExternalSemaphore_t semaphore = semaphore_.get();
    cudaExternalSemaphoreSignalParams params{};
    params.params.fence.value = value;
    check(cudaSignalExternalSemaphoresAsync(&semaphore, &params, 1, stream), "cudaSignalExternalSemaphoresAsync");
  }

 private:
  using Semaphore = OwnedHandle<cudaExternalSemaphore_t, cudaDestroyExternalSemaphore>;
  static Semaphore import_semaphore(const ExternalTimeline& timeline, const char* what) {
    cudaExternalSemaphoreHandleDesc handle{};
    handle.type = cudaExternalSemaphoreHandleTypeTimelineSemaphoreFd;
    handle.handle.fd = timeline.fd;
    return create_owned<cudaExternalSemaphore_t, cudaDestroyExternalSemaphore>(
        [&](cudaExternalSemaphore_t* semaphore) { return cudaImportExternalSemaphore(semaphore, &handle); }, what);
  }
  Semaphore semaphore_;
};

}  // namespace granular::cuda
