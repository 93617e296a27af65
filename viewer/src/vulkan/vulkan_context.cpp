#include "vulkan/vulkan_context.hpp"

#include <cstdint>
#include <cstdio>
#include <cstring>

#include "vulkan/vulkan_check.hpp"

namespace viewer {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                     void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    static_cast<VulkanContext*>(user)->count_validation_message();
    std::fprintf(stderr, "vulkan validation: %s\n", data->pMessage);
  }
  return VK_FALSE;
}

bool has_layer(const char* name) {
  std::uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const auto& layer : layers)
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

bool has_device_extension(VkPhysicalDevice device, const char* name) {
  std::uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  for (const auto& extension : extensions)
    if (std::strcmp(extension.extensionName, name) == 0) return true;
  return false;
}

int type_rank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

std::vector<const char*> device_extensions(const ContextOptions& options) {
  std::vector<const char*> names;
  if (options.make_surface) names.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  if (options.external_memory) {
    names.push_back(VK_KHR_EXTERNAL_MEMORY_FD_EXTENSION_NAME);
    names.push_back(VK_KHR_EXTERNAL_SEMAPHORE_FD_EXTENSION_NAME);
  }
  return names;
}

}  // namespace

bool validation_layer_available() { return has_layer(kValidationLayer); }

VulkanContext::VulkanContext(const ContextOptions& options) : external_memory_(options.external_memory) {
  try {
    create_instance(options);
    if (options.make_surface) surface_ = options.make_surface(instance_);
    pick_physical_device(options);
    create_device(options);
  } catch (...) {
    release();
    throw;
  }
}

VulkanContext::~VulkanContext() { release(); }

void VulkanContext::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
    if (messenger_) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
      if (destroy) destroy(instance_, messenger_, nullptr);
    }
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

void VulkanContext::create_instance(const ContextOptions& options) {
  std::uint32_t api_version = 0;
  if (vkEnumerateInstanceVersion(&api_version) != VK_SUCCESS || api_version < VK_API_VERSION_1_3)
    throw VulkanError("the Vulkan loader does not offer Vulkan 1.3; install libvulkan1 >= 1.3 and a driver "
                      "(mesa-vulkan-drivers for lavapipe, or the GPU vendor's)");
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "granular-sandbox";
  app.apiVersion = VK_API_VERSION_1_3;

  std::vector<const char*> extensions;
  for (const auto& name : options.instance_extensions) extensions.push_back(name.c_str());
  std::vector<const char*> layers;
  if (options.validation) {
    if (!has_layer(kValidationLayer))
      throw VulkanError("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                        "(apt-get install vulkan-validationlayers, or run without --validation)");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                          VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger.pfnUserCallback = on_validation_message;
  messenger.pUserData = this;

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledExtensionCount = std::uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  info.enabledLayerCount = std::uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  if (options.validation) info.pNext = &messenger;
  vk_check(vkCreateInstance(&info, nullptr, &instance_), "vkCreateInstance");
  if (options.validation) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (!create) throw VulkanError("VK_EXT_debug_utils is missing although the validation layer is present");
    vk_check(create(instance_, &messenger, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }
}

void VulkanContext::pick_physical_device(const ContextOptions& options) {
  std::uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance_, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance_, &count, devices.data());
  std::string rejected;
  int best_rank = 1 << 30;
  for (VkPhysicalDevice device : devices) {
    VkPhysicalDeviceIDProperties id{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ID_PROPERTIES};
    VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    properties.pNext = &id;
    vkGetPhysicalDeviceProperties2(device, &properties);
    const std::string name = properties.properties.deviceName;
    auto reject = [&](const std::string& why) { rejected += "\n  " + name + ": " + why; };
    if (properties.properties.apiVersion < VK_API_VERSION_1_3) { reject("no Vulkan 1.3"); continue; }
    if (options.device_uuid && std::memcmp(id.deviceUUID, options.device_uuid->data(), 16) != 0) {
      reject("not the CUDA device (UUID differs)");
      continue;
    }
    bool extensions_ok = true;
    for (const char* extension : device_extensions(options))
      if (!has_device_extension(device, extension)) { reject(std::string("no ") + extension); extensions_ok = false; break; }
    if (!extensions_ok) continue;
    VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &features12;
    vkGetPhysicalDeviceFeatures2(device, &features);
    if (!features.features.multiDrawIndirect || !features.features.drawIndirectFirstInstance ||
        !features.features.shaderClipDistance || !features12.storageBuffer8BitAccess || !features12.shaderInt8 ||
        !features12.timelineSemaphore || !features12.drawIndirectCount) {
      reject("lacks multiDrawIndirect, drawIndirectFirstInstance, shaderClipDistance, storageBuffer8BitAccess, shaderInt8, "
             "timelineSemaphore or drawIndirectCount");
      continue;
    }
    std::uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, families.data());
    std::optional<std::uint32_t> family;
    for (std::uint32_t i = 0; i < family_count; ++i) {
      const VkQueueFlags needed = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
      if ((families[i].queueFlags & needed) != needed) continue;
      if (surface_) {
        VkBool32 present = VK_FALSE;
        vkGetPhysicalDeviceSurfaceSupportKHR(device, i, surface_, &present);
        if (!present) continue;
      }
      family = i;
      break;
    }
    if (!family) { reject("no queue family with graphics, compute" + std::string(surface_ ? " and present" : "")); continue; }
    const int rank = type_rank(properties.properties.deviceType);
    if (rank >= best_rank) continue;
    best_rank = rank;
    physical_device_ = device;
    queue_family_ = *family;
    device_name_ = name;
    timestamp_period_ns_ = properties.properties.limits.timestampPeriod;
    has_timestamps_ = families[*family].timestampValidBits > 0;
  }
  if (!physical_device_)
    throw VulkanError("no usable Vulkan device" + (devices.empty() ? std::string(" (none found: install a driver, e.g. mesa-vulkan-drivers for lavapipe)")
                                                                   : ":" + rejected));
  vkGetPhysicalDeviceMemoryProperties(physical_device_, &memory_properties_);
}

void VulkanContext::create_device(const ContextOptions& options) {
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue.queueFamilyIndex = queue_family_;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;

  VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  features13.synchronization2 = VK_TRUE;
  features13.maintenance4 = VK_TRUE;  // glslc --target-env=vulkan1.3 emits LocalSizeId
  VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  features12.pNext = &features13;
  features12.storageBuffer8BitAccess = VK_TRUE;
  features12.shaderInt8 = VK_TRUE;
  features12.timelineSemaphore = VK_TRUE;
  features12.drawIndirectCount = VK_TRUE;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &features12;
  features.features.multiDrawIndirect = VK_TRUE;
  features.features.drawIndirectFirstInstance = VK_TRUE;
  features.features.shaderClipDistance = VK_TRUE;  // the marching cubes' section plane (mc.vert)

  const std::vector<const char*> extensions = device_extensions(options);
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &features;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue;
  info.enabledExtensionCount = std::uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  vk_check(vkCreateDevice(physical_device_, &info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool.queueFamilyIndex = queue_family_;
  vk_check(vkCreateCommandPool(device_, &pool, nullptr, &command_pool_), "vkCreateCommandPool");
}

std::uint32_t VulkanContext::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags properties) const {
  for (std::uint32_t i = 0; i < memory_properties_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (memory_properties_.memoryTypes[i].propertyFlags & properties) == properties) return i;
  throw VulkanError("no Vulkan memory type with the needed properties on " + device_name_);
}

void VulkanContext::run_once(const std::function<void(VkCommandBuffer)>& record) const {
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = command_pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  vk_check(vkAllocateCommandBuffers(device_, &allocate, &commands), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkBeginCommandBuffer(commands, &begin);
  record(commands);
  vk_check(vkEndCommandBuffer(commands), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  vk_check(vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit");
  vk_check(vkQueueWaitIdle(queue_), "vkQueueWaitIdle");
  vkFreeCommandBuffers(device_, command_pool_, 1, &commands);
}

}  // namespace viewer
