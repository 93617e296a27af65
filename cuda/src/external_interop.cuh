#pragma once
/// @file external_interop.cuh
/// Memory and timeline semaphores exported by a graphics API (opaque POSIX fds), imported into
/// CUDA: the cell buffer a renderer reads without a copy, and the semaphores that order the
/// simulation's writes with the renderer's reads.

#include <cuda_runtime.h>

#include <cstdint>
#include <string>
#include <utility>

#include "cuda_check.cuh"
#include "granular/errors.hpp"
#include "granular/external_memory.hpp"

namespace granular::cuda {

/// An imported allocation with `bytes` of it mapped as a device buffer; unmapped and released by
/// its destructor. Move-only.
class ImportedMemory {
 public:
  /// Imports `memory` and maps `bytes` from its offset. On success CUDA owns memory.fd; on failure
  /// (BackendError naming the CUDA error) the fd is still the caller's.
  ImportedMemory(const ExternalCellMemory& memory, std::uint64_t bytes) {
    cudaExternalMemoryHandleDesc handle{};
    handle.type = cudaExternalMemoryHandleTypeOpaqueFd;
    handle.handle.fd = memory.fd;
    handle.size = memory.allocation_size;
    handle.flags = memory.dedicated ? cudaExternalMemoryDedicated : 0u;
    check(cudaImportExternalMemory(&external_, &handle), "cudaImportExternalMemory (shared cell buffer)");
    cudaExternalMemoryBufferDesc buffer{};
    buffer.offset = memory.offset;
    buffer.size = bytes;
    void* mapped = nullptr;
    const cudaError_t status = cudaExternalMemoryGetMappedBuffer(&mapped, external_, &buffer);
    if (status != cudaSuccess) {
      cudaDestroyExternalMemory(external_);
      check(status, "cudaExternalMemoryGetMappedBuffer (shared cell buffer)");
    }
    data_ = static_cast<std::uint8_t*>(mapped);
  }
  ~ImportedMemory() {
    if (data_ != nullptr) cudaFree(data_);
    if (external_ != nullptr) cudaDestroyExternalMemory(external_);
  }
  ImportedMemory(ImportedMemory&& other) noexcept
      : external_(std::exchange(other.external_, nullptr)), data_(std::exchange(other.data_, nullptr)) {}
  ImportedMemory& operator=(ImportedMemory&&) = delete;
  ImportedMemory(const ImportedMemory&) = delete;
  ImportedMemory& operator=(const ImportedMemory&) = delete;
  /// The mapped device pointer.
  std::uint8_t* data() const { return data_; }

 private:
  cudaExternalMemory_t external_ = nullptr;
  std::uint8_t* data_ = nullptr;
};

/// An imported timeline semaphore. Move-only.
class ImportedTimeline {
 public:
  /// Imports `timeline`. On success CUDA owns timeline.fd; BackendError otherwise.
  ImportedTimeline(const ExternalTimeline& timeline, const char* what) {
    cudaExternalSemaphoreHandleDesc handle{};
    handle.type = cudaExternalSemaphoreHandleTypeTimelineSemaphoreFd;
    handle.handle.fd = timeline.fd;
    check(cudaImportExternalSemaphore(&semaphore_, &handle), what);
  }
  ~ImportedTimeline() {
    if (semaphore_ != nullptr) cudaDestroyExternalSemaphore(semaphore_);
  }
  ImportedTimeline(ImportedTimeline&& other) noexcept : semaphore_(std::exchange(other.semaphore_, nullptr)) {}
  ImportedTimeline& operator=(ImportedTimeline&&) = delete;
  ImportedTimeline(const ImportedTimeline&) = delete;
  ImportedTimeline& operator=(const ImportedTimeline&) = delete;

  /// Makes work enqueued on `stream` after this wait until the semaphore reaches `value`.
  void wait(std::uint64_t value, cudaStream_t stream) const {
    cudaExternalSemaphoreWaitParams params{};
    params.params.fence.value = value;
    check(cudaWaitExternalSemaphoresAsync(&semaphore_, &params, 1, stream), "cudaWaitExternalSemaphoresAsync");
  }
  /// Sets the semaphore to `value` once the work enqueued on `stream` so far is done.
  void signal(std::uint64_t value, cudaStream_t stream) const {
    cudaExternalSemaphoreSignalParams params{};
    params.params.fence.value = value;
    check(cudaSignalExternalSemaphoresAsync(&semaphore_, &params, 1, stream), "cudaSignalExternalSemaphoresAsync");
  }

 private:
  cudaExternalSemaphore_t semaphore_ = nullptr;
};

}  // namespace granular::cuda
