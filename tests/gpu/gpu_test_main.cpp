/// @file gpu_test_main.cpp
/// Entry point of the GPU test suite: runs the doctest cases when a CUDA device is usable, else
/// reports the suite as skipped (exit code 77, ctest's SKIP_RETURN_CODE).

#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <string>

#include "granular_cuda/cuda_backend_factory.hpp"

int main(int argc, char** argv) {
  std::string why;
  if (!granular::cuda_device_available(&why)) {
    std::printf("SKIPPED: no usable CUDA device: %s\n", why.c_str());
    return 77;
  }
  doctest::Context context(argc, argv);
  return context.run();
}
