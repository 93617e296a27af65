#pragma once
/// @file cuda_check.cuh
/// Turns CUDA runtime status codes into granular's typed exceptions.

#include <cuda_runtime.h>

#include <string>

#include "granular/errors.hpp"

namespace granular::cuda {

/// "<name> (<description>)" of a CUDA status, e.g. "cudaErrorNoDevice (no CUDA-capable device is detected)".
inline std::string error_text(cudaError_t status) {
  return std::string(cudaGetErrorName(status)) + " (" + cudaGetErrorString(status) + ")";
}

/// Throws BackendError "cuda backend: <what> failed: <error>" when `status` is not cudaSuccess.
/// Clears the runtime's last-error slot first, so a non-sticky error does not resurface in a later
/// unrelated call.
inline void check(cudaError_t status, const char* what) {
  if (status == cudaSuccess) return;
  cudaGetLastError();
  throw BackendError(std::string("cuda backend: ") + what + " failed: " + error_text(status));
}

/// Checks the launch of the kernels just enqueued (bad configuration, missing kernel image).
inline void check_launch(const char* what) { check(cudaGetLastError(), what); }

}  // namespace granular::cuda
