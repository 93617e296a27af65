#pragma once
/// @file input_tracker.hpp
/// Mouse and keyboard state of the window, sampled once a frame: cursor motion, buttons, wheel
/// steps since the last frame, and keys pressed this frame (edges) or held.

#include <array>

struct GLFWwindow;

namespace viewer {

/// One frame of input.
class InputTracker {
 public:
  /// Tracks `window`; installs the scroll callback (install it before ImGui's, which chains to it).
  explicit InputTracker(GLFWwindow* window);
  /// Samples the state; call once a frame after glfwPollEvents().
  void sample();

  /// Cursor position in framebuffer pixels.
  double x() const { return x_; }
  /// Cursor position in framebuffer pixels.
  double y() const { return y_; }
  /// Cursor motion since the previous sample, in framebuffer pixels.
  double dx() const { return x_ - previous_x_; }
  /// Cursor motion since the previous sample, in framebuffer pixels.
  double dy() const { return y_ - previous_y_; }
  /// Wheel steps since the previous sample (positive: away from the user).
  double scroll() const { return scroll_; }
  /// True while mouse button `button` (GLFW_MOUSE_BUTTON_*) is down.
  bool button(int button) const;
  /// True while key `key` (GLFW_KEY_*) is down.
  bool held(int key) const;
  /// True when key `key` went down since the previous sample.
  bool pressed(int key) const;

 private:
  static void on_scroll(GLFWwindow* window, double x, double y);

  GLFWwindow* window_;
  double x_ = 0, y_ = 0, previous_x_ = 0, previous_y_ = 0;
  double scroll_ = 0, pending_scroll_ = 0;
  std::array<bool, 512> keys_{}, previous_keys_{};
};

}  // namespace viewer
