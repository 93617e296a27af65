#pragma once
/// @file vulkan_context.hpp
/// The Vulkan instance, the validation messenger, the chosen physical device and the logical
/// device with its one graphics+compute queue: what every other viewer object borrows.

#include <vulkan/vulkan.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace viewer {

/// How to create a VulkanContext.
struct ContextOptions {
  /// Enables VK_LAYER_KHRONOS_validation and a messenger that counts its warnings and errors.
  bool validation = false;
  /// Instance extensions the caller needs (e.g. GLFW's surface extensions); none when headless.
  std::vector<std::string> instance_extensions;
  /// When set, creates the presentation surface once the instance exists; the chosen queue must
  /// then be able to present to it and the device gets VK_KHR_swapchain.
  std::function<VkSurfaceKHR(VkInstance)> make_surface;
  /// When set, only the physical device with this UUID is accepted (CUDA interop).
  std::optional<std::array<std::uint8_t, 16>> device_uuid;
  /// Enables the external-memory and external-semaphore (opaque fd) device extensions.
  bool external_memory = false;
};

/// True when the Khronos validation layer is installed (VK_LAYER_PATH included).
bool validation_layer_available();

/// Owns the instance, debug messenger, surface (if any), device and queue.
class VulkanContext {
 public:
  /// Creates everything; throws VulkanError with an actionable message when there is no Vulkan
  /// 1.3 device with a graphics+compute queue and the features the renderers need.
  explicit VulkanContext(const ContextOptions& options);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  /// The instance.
  VkInstance instance() const { return instance_; }
  /// The chosen physical device.
  VkPhysicalDevice physical_device() const { return physical_device_; }
  /// The logical device.
  VkDevice device() const { return device_; }
  /// The graphics+compute(+present) queue.
  VkQueue queue() const { return queue_; }
  /// Its family index.
  std::uint32_t queue_family() const { return queue_family_; }
  /// The surface made by ContextOptions::make_surface (VK_NULL_HANDLE when headless).
  VkSurfaceKHR surface() const { return surface_; }
  /// The device's name ("llvmpipe (LLVM 15.0.6, 256 bits)").
  const std::string& device_name() const { return device_name_; }
  /// Nanoseconds per timestamp tick.
  double timestamp_period_ns() const { return timestamp_period_ns_; }
  /// True when created with ContextOptions::external_memory (CUDA interop possible).
  bool external_memory() const { return external_memory_; }
  /// True when the queue supports timestamp queries.
  bool has_timestamps() const { return has_timestamps_; }

  /// Validation warnings and errors received so far (0 when validation is off).
  std::uint64_t validation_messages() const { return validation_messages_.load(); }
  /// Called by the debug messenger; counts one message.
  void count_validation_message() { ++validation_messages_; }

  /// A memory type index among `type_bits` with `properties`; throws VulkanError when none.
  std::uint32_t memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags properties) const;
  /// The command pool of the queue family (resettable command buffers).
  VkCommandPool command_pool() const { return command_pool_; }
  /// Records `record` into a fresh command buffer, submits it and waits for it to finish.
  void run_once(const std::function<void(VkCommandBuffer)>& record) const;

 private:
  void release();
  void create_instance(const ContextOptions& options);
  void pick_physical_device(const ContextOptions& options);
  void create_device(const ContextOptions& options);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_properties_{};
  std::string device_name_;
  double timestamp_period_ns_ = 1.0;
  bool has_timestamps_ = false;
  bool external_memory_ = false;
  std::atomic<std::uint64_t> validation_messages_{0};
};

}  // namespace viewer
