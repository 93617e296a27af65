#include "cells/shared_cells.hpp"

#include <cstdint>
#include <unistd.h>

#include <algorithm>
#include <string>
#include <utility>

#include "vulkan/barriers.hpp"
#include "granular/external_memory.hpp"
#include "granular/world.hpp"
#include "vulkan/gpu_buffer.hpp"
#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

constexpr VkExternalMemoryHandleTypeFlagBits kMemoryHandle = VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT;
constexpr VkExternalSemaphoreHandleTypeFlagBits kSemaphoreHandle = VK_EXTERNAL_SEMAPHORE_HANDLE_TYPE_OPAQUE_FD_BIT;
constexpr VkBufferUsageFlags kUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

template <typename Function>
Function device_function(VkDevice device, const char* name) {
  auto function = reinterpret_cast<Function>(vkGetDeviceProcAddr(device, name));
  if (!function) throw VulkanError(std::string(name) + " is missing: the device lacks external memory / semaphore fd support");
  return function;
}

// Closes an exported fd unless it was handed over.
struct FdGuard {
  int fd = -1;
  ~FdGuard() {
    if (fd >= 0) close(fd);
  }
};

}  // namespace

SharedCells::SharedCells(const VulkanContext& context, granular::World& world)
    : context_(context), world_(world), slots_(context) {
  try {
    create_memory(world);
    FdGuard ready_fd, released_fd;
    cells_ready_ = create_timeline(ready_fd.fd);
    cells_released_ = create_timeline(released_fd.fd);
    world.attach_timelines(granular::ExternalTimeline{ready_fd.fd}, granular::ExternalTimeline{released_fd.fd});
    ready_fd.fd = released_fd.fd = -1;  // granular owns them now
  } catch (...) {
    release();
    throw;
  }
}

SharedCells::~SharedCells() { release(); }

void SharedCells::release() noexcept {
  const VkDevice device = context_.device();
  vkDeviceWaitIdle(device);
  if (cells_ready_) vkDestroySemaphore(device, std::exchange(cells_ready_, VK_NULL_HANDLE), nullptr);
  if (cells_released_) vkDestroySemaphore(device, std::exchange(cells_released_, VK_NULL_HANDLE), nullptr);
  if (buffer_) vkDestroyBuffer(device, std::exchange(buffer_, VK_NULL_HANDLE), nullptr);
  if (memory_) vkFreeMemory(device, std::exchange(memory_, VK_NULL_HANDLE), nullptr);
}

void SharedCells::create_memory(granular::World& world) {
  const VkDevice device = context_.device();
  const std::uint64_t bytes = world.shared_cell_bytes();
  if (bytes == 0) throw VulkanError("the world's backend (" + world.backend_description() + ") cannot share its cells; use --backend cuda");

  VkPhysicalDeviceExternalBufferInfo query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_BUFFER_INFO};
  query.usage = kUsage;
  query.handleType = kMemoryHandle;
  VkExternalBufferProperties properties{VK_STRUCTURE_TYPE_EXTERNAL_BUFFER_PROPERTIES};
  vkGetPhysicalDeviceExternalBufferProperties(context_.physical_device(), &query, &properties);
  const VkExternalMemoryFeatureFlags features = properties.externalMemoryProperties.externalMemoryFeatures;
  if (!(features & VK_EXTERNAL_MEMORY_FEATURE_EXPORTABLE_BIT))
    throw VulkanError(context_.device_name() + " cannot export buffer memory as an opaque fd");

  VkExternalMemoryBufferCreateInfo external{VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_BUFFER_CREATE_INFO};
  external.handleTypes = kMemoryHandle;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.pNext = &external;
  info.size = (bytes + 3) / 4 * 4;
  info.usage = kUsage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  vk_check(vkCreateBuffer(device, &info, nullptr, &buffer_), "vkCreateBuffer (shared cells)");

  VkMemoryDedicatedRequirements dedicated_requirements{VK_STRUCTURE_TYPE_MEMORY_DEDICATED_REQUIREMENTS};
  VkMemoryRequirements2 requirements{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
  requirements.pNext = &dedicated_requirements;
  VkBufferMemoryRequirementsInfo2 requirements_info{VK_STRUCTURE_TYPE_BUFFER_MEMORY_REQUIREMENTS_INFO_2};
  requirements_info.buffer = buffer_;
  vkGetBufferMemoryRequirements2(device, &requirements_info, &requirements);
  dedicated_ = dedicated_requirements.requiresDedicatedAllocation || dedicated_requirements.prefersDedicatedAllocation ||
               (features & VK_EXTERNAL_MEMORY_FEATURE_DEDICATED_ONLY_BIT);

  VkMemoryDedicatedAllocateInfo dedicated{VK_STRUCTURE_TYPE_MEMORY_DEDICATED_ALLOCATE_INFO};
  dedicated.buffer = buffer_;
  VkExportMemoryAllocateInfo export_info{VK_STRUCTURE_TYPE_EXPORT_MEMORY_ALLOCATE_INFO};
  export_info.handleTypes = kMemoryHandle;
  export_info.pNext = dedicated_ ? &dedicated : nullptr;
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.pNext = &export_info;
  allocate.allocationSize = requirements.memoryRequirements.size;
  allocate.memoryTypeIndex =
      context_.memory_type(requirements.memoryRequirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  vk_check(vkAllocateMemory(device, &allocate, nullptr, &memory_), "vkAllocateMemory (shared cells)");
  vk_check(vkBindBufferMemory(device, buffer_, memory_, 0), "vkBindBufferMemory (shared cells)");

  auto get_memory_fd = device_function<PFN_vkGetMemoryFdKHR>(device, "vkGetMemoryFdKHR");
  VkMemoryGetFdInfoKHR fd_info{VK_STRUCTURE_TYPE_MEMORY_GET_FD_INFO_KHR};
  fd_info.memory = memory_;
  fd_info.handleType = kMemoryHandle;
  FdGuard fd;
  vk_check(get_memory_fd(device, &fd_info, &fd.fd), "vkGetMemoryFdKHR");
  world.share_cells(granular::ExternalCellMemory{fd.fd, allocate.allocationSize, 0, dedicated_});
  fd.fd = -1;  // granular owns it now
}

VkSemaphore SharedCells::create_timeline(int& fd) {
  const VkDevice device = context_.device();
  VkSemaphoreTypeCreateInfo type{VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO};
  type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
  type.initialValue = 0;
  VkPhysicalDeviceExternalSemaphoreInfo query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_SEMAPHORE_INFO};
  query.pNext = &type;
  query.handleType = kSemaphoreHandle;
  VkExternalSemaphoreProperties properties{VK_STRUCTURE_TYPE_EXTERNAL_SEMAPHORE_PROPERTIES};
  vkGetPhysicalDeviceExternalSemaphoreProperties(context_.physical_device(), &query, &properties);
  if (!(properties.externalSemaphoreFeatures & VK_EXTERNAL_SEMAPHORE_FEATURE_EXPORTABLE_BIT))
    throw VulkanError(context_.device_name() + " cannot export timeline semaphores as opaque fds");
  VkExportSemaphoreCreateInfo export_info{VK_STRUCTURE_TYPE_EXPORT_SEMAPHORE_CREATE_INFO};
  export_info.pNext = &type;
  export_info.handleTypes = kSemaphoreHandle;
  VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  info.pNext = &export_info;
  VkSemaphore semaphore = VK_NULL_HANDLE;
  vk_check(vkCreateSemaphore(device, &info, nullptr, &semaphore), "vkCreateSemaphore (timeline)");
  auto get_semaphore_fd = device_function<PFN_vkGetSemaphoreFdKHR>(device, "vkGetSemaphoreFdKHR");
  VkSemaphoreGetFdInfoKHR fd_info{VK_STRUCTURE_TYPE_SEMAPHORE_GET_FD_INFO_KHR};
  fd_info.semaphore = semaphore;
  fd_info.handleType = kSemaphoreHandle;
  const VkResult result = get_semaphore_fd(device, &fd_info, &fd);
  if (result < 0) {
    vkDestroySemaphore(device, semaphore, nullptr);
    vk_check(result, "vkGetSemaphoreFdKHR");
  }
  return semaphore;
}

void SharedCells::submit_snapshot(int slot, const std::function<void(VkCommandBuffer, VkBuffer)>& record_copy) {
  const granular::CellsHandoff handoff = world_.hand_off_cells();
  slots_.wait(slot);
  VkCommandBuffer commands = slots_.begin(slot);
  constexpr VkPipelineStageFlags2 kCopyStages = VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  // Acquire the shared buffer from CUDA (queue family "external") for transfers and shaders.
  VkBufferMemoryBarrier2 acquire = whole_buffer_barrier(buffer_, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, kCopyStages,
                                                        VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  acquire.srcQueueFamilyIndex = VK_QUEUE_FAMILY_EXTERNAL;
  acquire.dstQueueFamilyIndex = context_.queue_family();
  record_barrier(commands, acquire);
  record_copy(commands, buffer_);
  // Release it back to CUDA (nothing was written: no access to make available).
  VkBufferMemoryBarrier2 release =
      whole_buffer_barrier(buffer_, kCopyStages, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE);
  release.srcQueueFamilyIndex = context_.queue_family();
  release.dstQueueFamilyIndex = VK_QUEUE_FAMILY_EXTERNAL;
  record_barrier(commands, release);
  vk_check(vkEndCommandBuffer(commands), "vkEndCommandBuffer (interop)");

  VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  wait.semaphore = cells_ready_;
  wait.value = handoff.wait_ready;
  wait.stageMask = kCopyStages;
  VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
  signal.semaphore = cells_released_;
  signal.value = handoff.signal_released;
  signal.stageMask = kCopyStages;
  VkCommandBufferSubmitInfo command_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  command_info.commandBuffer = commands;
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.waitSemaphoreInfoCount = 1;
  submit.pWaitSemaphoreInfos = &wait;
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &command_info;
  submit.signalSemaphoreInfoCount = 1;
  submit.pSignalSemaphoreInfos = &signal;
  vk_check(vkQueueSubmit2(context_.queue(), 1, &submit, slots_.fence(slot)), "vkQueueSubmit2 (interop snapshot)");
}

std::optional<ContextOptions> interop_context(const granular::World& world, ContextOptions options) {
  if (world.backend() != granular::BackendKind::Cuda || world.shared_cell_bytes() == 0) return std::nullopt;
  const auto uuid = granular::cuda_device_uuid();
  if (!uuid) return std::nullopt;
  options.external_memory = true;
  options.device_uuid = *uuid;
  return options;
}

}  // namespace viewer
