#include "vulkan/shader_loader.hpp"

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <vector>

#include "vulkan/vulkan_check.hpp"

namespace viewer {

std::filesystem::path shader_dir() {
  const char* env = std::getenv("GRANULAR_SHADER_DIR");
  if (env && *env) return env;
  std::error_code ec;
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed =
        (executable.parent_path() / GRANULAR_VIEWER_INSTALLED_SHADER_DIR).lexically_normal();
    if (std::filesystem::is_directory(installed, ec)) return installed;
  }
  return GRANULAR_VIEWER_SHADER_DIR;
}

VkShaderModule load_shader(VkDevice device, const std::string& name) {
  const std::filesystem::path path = shader_dir() / (name + ".spv");
  std::ifstream file(path, std::ios::binary);
  if (!file)
    throw VulkanError("cannot read shader " + path.string() +
                      " (build the viewer_shaders target, or set GRANULAR_SHADER_DIR to a folder of .spv files)");
  const std::vector<char> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (bytes.empty() || bytes.size() % 4 != 0) throw VulkanError("shader " + path.string() + " is not SPIR-V");
  std::vector<std::uint32_t> words(bytes.size() / 4);
  std::copy(bytes.begin(), bytes.end(), reinterpret_cast<char*>(words.data()));
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = bytes.size();
  info.pCode = words.data();
  VkShaderModule module = VK_NULL_HANDLE;
  vk_check(vkCreateShaderModule(device, &info, nullptr, &module), ("vkCreateShaderModule " + name).c_str());
  return module;
}

}  // namespace viewer
