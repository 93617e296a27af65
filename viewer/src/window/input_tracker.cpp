#include "window/input_tracker.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace viewer {

InputTracker::InputTracker(GLFWwindow* window) : window_(window) {
  glfwSetWindowUserPointer(window, this);
  glfwSetKeyCallback(window, &InputTracker::on_key);
  glfwSetCharCallback(window, &InputTracker::on_char);
  glfwSetMouseButtonCallback(window, &InputTracker::on_mouse_button);
  glfwSetScrollCallback(window, &InputTracker::on_scroll);
  glfwSetDropCallback(window, &InputTracker::on_drop);
  sample();
  previous_x_ = x_;
  previous_y_ = y_;
}

InputTracker::~InputTracker() {
  glfwSetKeyCallback(window_, nullptr);
  glfwSetCharCallback(window_, nullptr);
  glfwSetMouseButtonCallback(window_, nullptr);
  glfwSetScrollCallback(window_, nullptr);
  glfwSetDropCallback(window_, nullptr);
  glfwSetWindowUserPointer(window_, nullptr);
}

InputTracker& InputTracker::of(GLFWwindow* window) { return *static_cast<InputTracker*>(glfwGetWindowUserPointer(window)); }

void InputTracker::on_key(GLFWwindow* window, int key, int, int action, int mods) {
  InputTracker& self = of(window);
  if (key < 0 || key >= int(self.keys_down_.size())) return;  // GLFW_KEY_UNKNOWN
  if (action == GLFW_PRESS) {
    self.keys_down_[key] = true;
    self.keys_pressed_[key] = true;
    self.pending_events_.push_back({InputEvent::Kind::KeyPress, key, mods, {}});
  } else if (action == GLFW_RELEASE) {
    self.keys_down_[key] = false;
  }
}

void InputTracker::on_char(GLFWwindow* window, unsigned int codepoint) {
  of(window).pending_events_.push_back({InputEvent::Kind::Character, int(codepoint), 0, {}});
}

void InputTracker::on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
  InputTracker& self = of(window);
  if (button < 0 || button >= int(self.buttons_down_.size())) return;
  const bool down = action == GLFW_PRESS;
  self.buttons_down_[button] = down;
  self.pending_events_.push_back(
      {down ? InputEvent::Kind::ButtonPress : InputEvent::Kind::ButtonRelease, button, mods, {}});
}

void InputTracker::on_scroll(GLFWwindow* window, double, double y) { of(window).pending_scroll_ += y; }

void InputTracker::on_drop(GLFWwindow* window, int count, const char** paths) {
  for (int i = 0; i < count; ++i) of(window).pending_events_.push_back({InputEvent::Kind::Drop, 0, 0, paths[i]});
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
  events_.swap(pending_events_);
  pending_events_.clear();
  for (std::size_t key = 0; key < keys_down_.size(); ++key) keys_held_[key] = keys_down_[key] || keys_pressed_[key];
  keys_pressed_.fill(false);
  buttons_held_ = buttons_down_;
}

bool InputTracker::button(int button) const { return button >= 0 && button < int(buttons_held_.size()) && buttons_held_[button]; }

bool InputTracker::held(int key) const { return key >= 0 && key < int(keys_held_.size()) && keys_held_[key]; }

}  // namespace viewer
