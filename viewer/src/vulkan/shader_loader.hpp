#pragma once
/// @file shader_loader.hpp
/// Loads the SPIR-V the build compiled (or copied from GRANULAR_SPIRV_DIR), or the installed copy,
/// into shader modules.

#include <vulkan/vulkan.h>

#include <filesystem>
#include <string>

namespace viewer {

/// The SPIR-V folder: $GRANULAR_SHADER_DIR when set; else, for an installed program, the install
/// tree's (GRANULAR_VIEWER_INSTALLED_SHADER_DIR relative to the running executable's folder,
/// <prefix>/share/granular/spirv from <prefix>/bin) when it exists; else the build tree's.
std::filesystem::path shader_dir();

/// Creates a module from "<shader_dir()>/<name>.spv" (e.g. "cube.vert"). Throws VulkanError naming
/// the file when it is missing or malformed.
VkShaderModule load_shader(VkDevice device, const std::string& name);

}  // namespace viewer
