#include "input_tracker.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace viewer {

InputTracker::InputTracker(GLFWwindow* window) : window_(window) {
  glfwSetWindowUserPointer(window, this);
  glfwSetScrollCallback(window, &InputTracker::on_scroll);
  sample();
  previous_x_ = x_;
  previous_y_ = y_;
}

void InputTracker::on_scroll(GLFWwindow* window, double, double y) {
  static_cast<InputTracker*>(glfwGetWindowUserPointer(window))->pending_scroll_ += y;
}

void InputTracker::sample() {
  previous_x_ = x_;
  previous_y_ = y_;
  double cursor_x = 0, cursor_y = 0;
  glfwGetCursorPos(window_, &cursor_x, &cursor_y);
  // Cursor positions are in window coordinates; scale to framebuffer pixels (HiDPI).
  int window_w = 1, window_h = 1, frame_w = 1, frame_h = 1;
  glfwGetWindowSize(window_, &window_w, &window_h);
  glfwGetFramebufferSize(window_, &frame_w, &frame_h);
  x_ = cursor_x * (window_w ? double(frame_w) / window_w : 1.0);
  y_ = cursor_y * (window_h ? double(frame_h) / window_h : 1.0);
  scroll_ = pending_scroll_;
  pending_scroll_ = 0;
  previous_keys_ = keys_;
  for (int key = GLFW_KEY_SPACE; key < int(keys_.size()); ++key) keys_[key] = glfwGetKey(window_, key) == GLFW_PRESS;
}

bool InputTracker::button(int button) const { return glfwGetMouseButton(window_, button) == GLFW_PRESS; }

bool InputTracker::held(int key) const { return key >= 0 && key < int(keys_.size()) && keys_[key]; }

bool InputTracker::pressed(int key) const { return held(key) && !previous_keys_[key]; }

}  // namespace viewer
