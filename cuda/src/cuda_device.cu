#include <cuda_runtime.h>

#include <cstdio>

#include "cuda_check.cuh"
#include "cuda_device.cuh"
#include "granular/extend/block.hpp"
#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular_cuda/cuda_backend_factory.hpp"

namespace granular {

namespace cuda {

namespace {

/// An empty kernel: if the device can load it, it can load every kernel of this build (all are
/// compiled for the same architectures).
__global__ void probe_kernel() {}

/// Why no device is usable, or an empty string when the current one is.
std::string unusable_reason() {
  int count = 0;
  cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess) {
    cudaGetLastError();
    if (status == cudaErrorNoDevice || status == cudaErrorInsufficientDriver)
      return "no NVIDIA GPU with a working driver on this machine (cudaGetDeviceCount: " + error_text(status) + ")";
    return "cudaGetDeviceCount failed: " + error_text(status);
  }
  if (count == 0) return "the CUDA driver reports no device";
  int index = 0;
  status = cudaGetDevice(&index);
  if (status != cudaSuccess) {
    cudaGetLastError();
    return "cudaGetDevice failed: " + error_text(status);
  }
  cudaFuncAttributes attributes{};
  status = cudaFuncGetAttributes(&attributes, probe_kernel);
  if (status != cudaSuccess) {
    cudaGetLastError();
    cudaDeviceProp prop{};
    std::string which = "device " + std::to_string(index);
    if (cudaGetDeviceProperties(&prop, index) == cudaSuccess)
      which += " (" + std::string(prop.name) + ", sm_" + std::to_string(prop.major) + std::to_string(prop.minor) + ")";
    else
      cudaGetLastError();
    return which + " cannot run this build's kernels: " + error_text(status);
  }
  return {};
}

std::string human_bytes(double bytes) {
  char text[64];
  if (bytes >= 1024.0 * 1024 * 1024)
    std::snprintf(text, sizeof text, "%.2f GiB", bytes / (1024.0 * 1024 * 1024));
  else
    std::snprintf(text, sizeof text, "%.2f MiB", bytes / (1024.0 * 1024));
  return text;
}

}  // namespace

DeviceInfo acquire_device() {
  const std::string reason = unusable_reason();
  if (!reason.empty()) throw BackendError("cuda backend: no usable CUDA device: " + reason);
  DeviceInfo info;
  check(cudaGetDevice(&info.index), "cudaGetDevice");
  check(cudaSetDevice(info.index), "cudaSetDevice");
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, info.index), "cudaGetDeviceProperties");
  info.name = prop.name;
  info.major = prop.major;
  info.minor = prop.minor;
  info.sm_count = prop.multiProcessorCount;
  return info;
}

std::string describe(const DeviceInfo& device) {
  return "cuda (" + device.name + ", sm_" + std::to_string(device.major) + std::to_string(device.minor) + ")";
}

void check_fits(const DeviceInfo& device, Int3 size) {
  if (size.x <= 0 || size.y <= 0 || size.z <= 0)
    throw InvalidArgument("cuda backend: grid size " + to_string(size) + " has a non-positive extent");
  std::size_t free_bytes = 0, total_bytes = 0;
  check(cudaMemGetInfo(&free_bytes, &total_bytes), "cudaMemGetInfo");
  const std::uint64_t need = cuda_bytes_needed(size);
  if (need <= free_bytes) return;
  const std::uint64_t cells = std::uint64_t(size.x) * std::uint64_t(size.y) * std::uint64_t(size.z);
  throw OutOfMemory("cuda backend: a " + to_string(size) + " grid (" + std::to_string(cells) + " cells) needs " +
                    std::to_string(need) + " bytes (" + human_bytes(double(need)) +
                    ": 1 byte per cell plus 128 MiB of tables) on the device, but " + device.name + " has " +
                    std::to_string(free_bytes) + " bytes (" + human_bytes(double(free_bytes)) + ") free of " +
                    std::to_string(total_bytes) + " (" + human_bytes(double(total_bytes)) + ")");
}

}  // namespace cuda

bool cuda_device_available(std::string* why) {
  const std::string reason = cuda::unusable_reason();
  if (why != nullptr) *why = reason;
  return reason.empty();
}

std::uint64_t cuda_bytes_needed(Int3 size) {
  const std::uint64_t cells = std::uint64_t(size.x > 0 ? size.x : 0) * std::uint64_t(size.y > 0 ? size.y : 0) *
                              std::uint64_t(size.z > 0 ? size.z : 0);
  return cuda::cell_buffer_bytes(cells) + 2 * std::uint64_t(kBlockKeyCount) * sizeof(Transition);
}

std::array<std::uint8_t, 16> cuda_device_uuid_of_current() {
  const cuda::DeviceInfo device = cuda::acquire_device();
  cudaDeviceProp prop{};
  cuda::check(cudaGetDeviceProperties(&prop, device.index), "cudaGetDeviceProperties");
  std::array<std::uint8_t, 16> uuid{};
  for (std::size_t i = 0; i < uuid.size(); ++i) uuid[i] = std::uint8_t(prop.uuid.bytes[i]);
  return uuid;
}

void check_cuda_fits(Int3 size) {
  if (size.x <= 0 || size.y <= 0 || size.z <= 0)
    throw InvalidArgument("cuda backend: grid size " + to_string(size) + " has a non-positive extent");
  cuda::check_fits(cuda::acquire_device(), size);
}

}  // namespace granular
