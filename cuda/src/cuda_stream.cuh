#pragma once
/// @file cuda_stream.cuh
/// Owning, move-only wrappers of a CUDA stream and a CUDA event.

#include <cuda_runtime.h>

#include <utility>

#include "cuda_check.cuh"

namespace granular::cuda {

/// A stream of its own (ordered with the legacy default stream, so nothing races it).
class Stream {
 public:
  /// Creates the stream on the current device. Throws BackendError.
  Stream() { check(cudaStreamCreate(&stream_), "cudaStreamCreate"); }
  ~Stream() {
    if (stream_ != nullptr) cudaStreamDestroy(stream_);
  }
  Stream(Stream&& other) noexcept : stream_(std::exchange(other.stream_, nullptr)) {}
  Stream& operator=(Stream&&) = delete;
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;

  /// The raw handle.
  cudaStream_t get() const { return stream_; }
  /// Waits for everything enqueued so far; throws BackendError naming `what` on any error,
  /// including a kernel that failed asynchronously.
  void synchronize(const char* what) const { check(cudaStreamSynchronize(stream_), what); }

 private:
  cudaStream_t stream_ = nullptr;
};

/// A timing event.
class Event {
 public:
  /// Creates the event on the current device. Throws BackendError.
  Event() { check(cudaEventCreate(&event_), "cudaEventCreate"); }
  ~Event() {
    if (event_ != nullptr) cudaEventDestroy(event_);
  }
  Event(Event&& other) noexcept : event_(std::exchange(other.event_, nullptr)) {}
  Event& operator=(Event&&) = delete;
  Event(const Event&) = delete;
  Event& operator=(const Event&) = delete;

  /// Records the event on `stream`.
  void record(cudaStream_t stream) { check(cudaEventRecord(event_, stream), "cudaEventRecord"); }
  /// Milliseconds from `start` to this event; waits for this event to complete.
  float ms_since(const Event& start) const {
    check(cudaEventSynchronize(event_), "cudaEventSynchronize");
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start.event_, event_), "cudaEventElapsedTime");
    return ms;
  }

 private:
  cudaEvent_t event_ = nullptr;
};

}  // namespace granular::cuda
