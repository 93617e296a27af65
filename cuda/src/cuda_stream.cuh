#pragma once
/// @file cuda_stream.cuh
/// Owning, move-only wrappers of a CUDA stream and a CUDA event.

#include <cuda_runtime.h>

#include "cuda_check.cuh"
#include "owned_handle.cuh"

namespace granular::cuda {

/// A stream of its own (ordered with the legacy default stream, so nothing races it). Move-only.
class Stream {
 public:
  /// Creates the stream on the current device. Throws BackendError.
  Stream()
      : stream_(create_owned<cudaStream_t, cudaStreamDestroy>([](cudaStream_t* s) { return cudaStreamCreate(s); },
                                                               "cudaStreamCreate")) {}

  /// The raw handle.
  cudaStream_t get() const { return stream_.get(); }
  /// Waits for everything enqueued so far; throws BackendError naming `what` on any error,
  /// including a kernel that failed asynchronously.
  void synchronize(const char* what) const { check(cudaStreamSynchronize(stream_.get()), what); }

 private:
  OwnedHandle<cudaStream_t, cudaStreamDestroy> stream_;
};

/// A timing event. Move-only.
class Event {
 public:
  /// Creates the event on the current device. Throws BackendError.
  Event()
      : event_(create_owned<cudaEvent_t, cudaEventDestroy>([](cudaEvent_t* e) { return cudaEventCreate(e); },
                                                            "cudaEventCreate")) {}

  /// Records the event on `stream`.
  void record(cudaStream_t stream) { check(cudaEventRecord(event_.get(), stream), "cudaEventRecord"); }
  /// Milliseconds from `start` to this event; waits for this event to complete.
  float ms_since(const Event& start) const {
    check(cudaEventSynchronize(event_.get()), "cudaEventSynchronize");
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start.event_.get(), event_.get()), "cudaEventElapsedTime");
    return ms;
  }

 private:
  OwnedHandle<cudaEvent_t, cudaEventDestroy> event_;
};

}  // namespace granular::cuda
