/// @file viewer_test_main.cpp
/// Entry point of the viewer tests (lavapipe in CI): doctest, then a check that the validation
/// layer reported nothing during the whole run.

#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>

#include "viewer_test_support.hpp"

int main(int argc, char** argv) {
  doctest::Context runner(argc, argv);
  const int status = runner.run();
  if (runner.shouldExit()) return status;
  const auto messages = viewer::test::context().validation_messages();
  if (messages != 0) {
    std::fprintf(stderr, "FAILED: %llu Vulkan validation messages (printed above)\n", static_cast<unsigned long long>(messages));
    return 1;
  }
  return status;
}
