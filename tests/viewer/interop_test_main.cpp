/// @file interop_test_main.cpp
/// Entry point of the CUDA-interop viewer tests: they need a CUDA device that Vulkan also sees
/// (same UUID); elsewhere (CI, CPU-only builds) the suite reports itself skipped with exit code 77.

#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <exception>

#include "granular/external_memory.hpp"
#include "interop_test_support.hpp"

int main(int argc, char** argv) {
  if (!granular::cuda_device_uuid()) {
    std::printf("SKIPPED: no usable CUDA device (or a build without the CUDA backend)\n");
    return 77;
  }
  try {
    viewer::test::interop_context();
  } catch (const std::exception& e) {
    std::printf("SKIPPED: no Vulkan device matching the CUDA device: %s\n", e.what());
    return 77;
  }
  doctest::Context runner(argc, argv);
  const int status = runner.run();
  if (runner.shouldExit()) return status;
  const auto messages = viewer::test::interop_context().validation_messages();
  if (messages != 0) {
    std::fprintf(stderr, "FAILED: %llu Vulkan validation messages (printed above)\n", static_cast<unsigned long long>(messages));
    return 1;
  }
  return status;
}
