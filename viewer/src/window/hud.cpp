#include "window/hud.hpp"

#include <cstdint>
#include <array>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>

#include "window/glfw_window.hpp"
#include "vulkan/vulkan_check.hpp"
#include "vulkan/vulkan_context.hpp"

namespace viewer {
namespace {

void check_imgui_result(VkResult result) { vk_check(result, "Dear ImGui Vulkan backend"); }

}  // namespace

Hud::Hud(const VulkanContext& context, const GlfwWindow& window, VkRenderPass render_pass, std::uint32_t min_image_count,
         std::uint32_t image_count)
    : device_(context.device()) {
  const std::array<VkDescriptorPoolSize, 1> sizes{{{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}}};
  VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pool.maxSets = 16;
  pool.poolSizeCount = std::uint32_t(sizes.size());
  pool.pPoolSizes = sizes.data();
  vk_check(vkCreateDescriptorPool(device_, &pool, nullptr, &pool_), "vkCreateDescriptorPool (HUD)");

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForVulkan(window.handle(), true);
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = context.instance();
  info.PhysicalDevice = context.physical_device();
  info.Device = context.device();
  info.QueueFamily = context.queue_family();
  info.Queue = context.queue();
  info.DescriptorPool = pool_;
  info.Subpass = 0;
  info.MinImageCount = min_image_count;
  info.ImageCount = image_count;
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = check_imgui_result;
  ImGui_ImplVulkan_Init(&info, render_pass);
  context.run_once([](VkCommandBuffer commands) { ImGui_ImplVulkan_CreateFontsTexture(commands); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

Hud::~Hud() {
  vkDeviceWaitIdle(device_);
  if (frame_open_) ImGui::EndFrame();
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  vkDestroyDescriptorPool(device_, pool_, nullptr);
}

void Hud::begin() {
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  frame_open_ = true;
}

void Hud::record(VkCommandBuffer commands) {
  ImGui::Render();
  frame_open_ = false;
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), commands);
}

void Hud::set_min_image_count(std::uint32_t count) { ImGui_ImplVulkan_SetMinImageCount(count); }

bool Hud::wants_mouse() const { return ImGui::GetIO().WantCaptureMouse; }

bool Hud::wants_keyboard() const { return ImGui::GetIO().WantCaptureKeyboard; }

}  // namespace viewer
