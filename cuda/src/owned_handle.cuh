#pragma once
/// @file owned_handle.cuh
/// The ownership of a CUDA runtime handle (a stream, an event, imported memory, an imported
/// semaphore, a mapped device pointer): one std::unique_ptr with the function that destroys it, so
/// every wrapper of a handle is move-only and releases it in its destructor, on every path.

#include <cuda_runtime.h>

#include <memory>
#include <type_traits>

#include "cuda_check.cuh"

namespace granular::cuda {

/// Calls `destroy` (cudaStreamDestroy, cudaEventDestroy, ...) on the handle it is given; its status
/// is ignored, as a destructor has nowhere to report it.
template <auto destroy>
struct HandleDestroyer {
  /// Destroys `handle`.
  template <class Handle>
  void operator()(Handle handle) const noexcept {
    destroy(handle);
  }
};

/// Owns a CUDA handle of pointer type `Handle` (null: none) and destroys it with `destroy` when it
/// goes out of scope.
template <class Handle, auto destroy>
using OwnedHandle = std::unique_ptr<std::remove_pointer_t<Handle>, HandleDestroyer<destroy>>;

/// A handle `create(&handle)` makes (e.g. a lambda calling cudaStreamCreate), owned. Throws
/// BackendError naming `what` when it fails.
template <class Handle, auto destroy, class Create>
OwnedHandle<Handle, destroy> create_owned(Create&& create, const char* what) {
  Handle handle = nullptr;
  check(create(&handle), what);
  return OwnedHandle<Handle, destroy>(handle);
}

}  // namespace granular::cuda
