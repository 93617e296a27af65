#pragma once
/// @file cuda_device.cuh
/// The device the CUDA backend runs on: availability, identity, and the free-memory check.

#include <cstdint>
#include <string>

#include "granular/geometry.hpp"

namespace granular::cuda {

/// Facts about one CUDA device.
struct DeviceInfo {
  int index = 0;          ///< CUDA device ordinal
  std::string name;       ///< e.g. "NVIDIA H100 80GB HBM3"
  int major = 0;          ///< compute capability, major
  int minor = 0;          ///< compute capability, minor
  int sm_count = 0;       ///< streaming multiprocessors
};

/// Makes the calling thread's current CUDA device (ordinal 0 unless the application chose another)
/// current and returns its facts. Throws BackendError, saying why, when no device is usable.
DeviceInfo acquire_device();

/// "cuda (<name>, sm_XY)".
std::string describe(const DeviceInfo& device);

/// Throws OutOfMemory naming `size`, the bytes needed (cuda_bytes_needed) and the bytes free on
/// `device` (already current) when the grid does not fit; BackendError when the query fails.
void check_fits(const DeviceInfo& device, Int3 size);

/// Bytes of device memory a cell buffer of `cells` cells occupies (whole 8-byte words).
inline std::uint64_t cell_buffer_bytes(std::uint64_t cells) { return (cells + 7) / 8 * 8; }

}  // namespace granular::cuda
