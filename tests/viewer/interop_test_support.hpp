#pragma once
/// @file interop_test_support.hpp
/// The interop tests' context: validation on, external memory, the CUDA device's UUID.

#include "vulkan/vulkan_context.hpp"

namespace viewer::test {

/// The process-wide interop context; throws VulkanError when no Vulkan device matches CUDA's.
VulkanContext& interop_context();

}  // namespace viewer::test
