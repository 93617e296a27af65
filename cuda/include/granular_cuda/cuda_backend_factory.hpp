#pragma once
/// @file cuda_backend_factory.hpp
/// The CUDA backend's entry points, as plain C++ (no CUDA types): the registration of the backend
/// (cuda_backend_registration.cpp) and the GPU tests include this with an ordinary C++ compiler and
/// link the granular_cuda library. A World finds the backend through the core's registry
/// (granular/extend/backend_registry.hpp), never through this header.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "granular/extend/backend.hpp"
#include "granular/extend/backend_factory.hpp"
#include "granular/extend/block.hpp"
#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_set.hpp"

namespace granular {

/// True when a CUDA device is usable (a driver, a device, and kernels of this build that run on
/// it); otherwise `why` (when given) says why (no driver, no device, unsupported architecture...).
bool cuda_device_available(std::string* why = nullptr);

/// The UUID of the CUDA device the backend would use (the calling thread's current device).
/// Throws BackendError when no device is usable.
std::array<std::uint8_t, 16> cuda_device_uuid_of_current();

/// Bytes the CUDA backend needs on the device for a grid of `size`: one byte per cell (rounded up
/// to whole 8-byte words) plus the 64 MiB transition table and the 64 MiB result table derived
/// from it on the device.
std::uint64_t cuda_bytes_needed(Int3 size);

/// Throws OutOfMemory, naming the grid size, the bytes needed and the bytes free on the device, when
/// a grid of `size` does not fit in the device's free memory; BackendError when no device is usable;
/// InvalidArgument for a non-positive extent. Allocates nothing.
void check_cuda_fits(Int3 size);

/// Creates the CUDA backend holding a copy of info.initial (a BackendFactory); info.sparse steps
/// only awake bricks (the same result as dense stepping); with it, a step() call runs the dense
/// kernels in their recording form when more than info.cuda.dense_fraction (0..1; 0 always, 1
/// never) of the bricks were awake at the last tick the host knows of. info.threads and
/// info.task_system are not used. Throws BackendError (no GPU, CUDA failure, with the CUDA error
/// string) or OutOfMemory (with the grid size, bytes needed and bytes free on the device);
/// InvalidArgument for an empty grid, a null table or rule set, or a dense_fraction outside 0..1.
std::unique_ptr<Backend> make_cuda_backend(const BackendCreateInfo& info);

/// Builds the transition table for `rules` on the GPU (rules.device_rule must be "paper" or
/// "motion", else InvalidArgument), returns the 16,777,216 entries (copied back), and the kernel time in
/// milliseconds in `kernel_ms` when given. Throws BackendError as make_cuda_backend.
std::vector<Transition> build_lut_on_gpu(const RuleSet& rules, float* kernel_ms = nullptr);

}  // namespace granular
