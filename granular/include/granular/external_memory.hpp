#pragma once
/// @file external_memory.hpp
/// Sharing the cell buffer with a graphics API without a copy (CUDA backend): the renderer
/// allocates exportable memory (Vulkan: VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT), the World
/// imports it and steps the cells in place, and two exported timeline semaphores order the
/// simulation's writes with the renderer's reads. No graphics or CUDA type appears here.

#include <array>
#include <cstdint>
#include <optional>

namespace granular {

/// Memory exported by a graphics API as an opaque POSIX file descriptor.
struct ExternalCellMemory {
  int fd = -1;                       ///< the exported handle; on success granular owns (and closes) it
  std::uint64_t allocation_size = 0;  ///< size of the whole exported allocation in bytes
  std::uint64_t offset = 0;          ///< where the cell buffer starts inside the allocation
  bool dedicated = false;            ///< true when allocated as a dedicated allocation (Vulkan's
                                     ///< VkMemoryDedicatedAllocateInfo), which the import must be told
};

/// A timeline semaphore exported by a graphics API as an opaque POSIX file descriptor.
struct ExternalTimeline {
  int fd = -1;  ///< the exported handle; on success granular owns (and closes) it
};

/// What a renderer does with the shared cells in one frame (see World::hand_off_cells): wait on the
/// device until `cells_ready` >= wait_ready, read the cells, then signal `cells_released` =
/// signal_released. Until that signal, every World call that writes cells waits on the device.
struct CellsHandoff {
  std::uint64_t wait_ready = 0;       ///< value of cells_ready that covers every write so far
  std::uint64_t signal_released = 0;  ///< value to signal on cells_released once reading is done
};

/// The 16-byte UUID of the CUDA device a World with the CUDA backend would use (compare with
/// VkPhysicalDeviceIDProperties::deviceUUID to pick the same GPU in Vulkan); nullopt when this
/// program links no CUDA backend (backend_registry.hpp) or no CUDA device is usable.
std::optional<std::array<std::uint8_t, 16>> cuda_device_uuid();

}  // namespace granular
