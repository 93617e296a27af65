#pragma once
/// @file device_buffer.cuh
/// An owning, move-only array in device memory: freed by its destructor, so no exception can leak it.

#include <cuda_runtime.h>

#include <cstddef>
#include <string>
#include <utility>

#include "cuda_check.cuh"
#include "granular/errors.hpp"

namespace granular::cuda {

/// `count` elements of T in device global memory (uninitialised).
template <class T>
class DeviceBuffer {
 public:
  /// An empty buffer (no allocation).
  DeviceBuffer() = default;
  /// Allocates `count` elements. Throws OutOfMemory when the device has no room (naming `what` and
  /// the bytes), BackendError for any other CUDA failure.
  DeviceBuffer(std::size_t count, const char* what) : count_(count) {
    if (count == 0) return;
    const cudaError_t status = cudaMalloc(reinterpret_cast<void**>(&data_), count * sizeof(T));
    if (status == cudaErrorMemoryAllocation) {
      cudaGetLastError();
      data_ = nullptr;
      throw OutOfMemory(std::string("cuda backend: could not allocate ") + std::to_string(count * sizeof(T)) +
                        " bytes of device memory for " + what);
    }
    check(status, what);
  }
  ~DeviceBuffer() { reset(); }
  DeviceBuffer(DeviceBuffer&& other) noexcept
      : data_(std::exchange(other.data_, nullptr)), count_(std::exchange(other.count_, 0)) {}
  DeviceBuffer& operator=(DeviceBuffer&& other) noexcept {
    if (this != &other) {
      reset();
      data_ = std::exchange(other.data_, nullptr);
      count_ = std::exchange(other.count_, 0);
    }
    return *this;
  }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;

  /// Frees the memory now (the buffer becomes empty).
  void reset() noexcept {
    if (data_ != nullptr) cudaFree(data_);
    data_ = nullptr;
    count_ = 0;
  }
  /// Device pointer to the first element (null when empty).
  T* data() const { return data_; }
  /// Number of elements.
  std::size_t size() const { return count_; }
  /// Size in bytes.
  std::size_t bytes() const { return count_ * sizeof(T); }

 private:
  T* data_ = nullptr;
  std::size_t count_ = 0;
};

}  // namespace granular::cuda
