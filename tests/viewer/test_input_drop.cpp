/// @file test_input_drop.cpp
/// Under Xvfb: files dropped on the window reach InputTracker's queue as Drop events, one per file
/// in the order given, among the frame's other events. The drop is delivered through the callback
/// the tracker installed (an X server drag and drop cannot be scripted), as GLFW calls it.

#include <doctest/doctest.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "window/glfw_window.hpp"
#include "window/input_tracker.hpp"

using namespace viewer;

TEST_CASE("input: files dropped on the window are queued as Drop events, one per file, in order") {
  GlfwWindow window(160, 120, "drop test");
  InputTracker input(window.handle());
  // glfwSetDropCallback returns the callback it replaces: the tracker's, which is put back.
  const GLFWdropfun tracker_drop = glfwSetDropCallback(window.handle(), nullptr);
  const bool installed = tracker_drop != nullptr;
  REQUIRE(installed);
  glfwSetDropCallback(window.handle(), tracker_drop);
  const char* paths[] = {"/tmp/a world.gsnap", "scene.VOX"};
  tracker_drop(window.handle(), 2, paths);
  input.sample();
  REQUIRE(input.events().size() == 2);
  CHECK(input.events()[0].kind == InputEvent::Kind::Drop);
  CHECK(input.events()[0].path == "/tmp/a world.gsnap");
  CHECK(input.events()[1].path == "scene.VOX");
  input.sample();
  CHECK(input.events().empty());
}
