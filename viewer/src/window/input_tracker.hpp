#pragma once
/// @file input_tracker.hpp
/// Mouse and keyboard input of the window, from GLFW's callbacks: every key press, typed character,
/// button press or release and file dropped on the window between two frames is queued, so a tap
/// shorter than a frame (a press and its release handled by the same glfwPollEvents) still counts.
/// The cursor position is sampled once a frame.

#include <array>
#include <string>
#include <vector>

struct GLFWwindow;

namespace viewer {

/// A key press, a mouse button press or release, or a file dropped, in the order they happened.
struct InputEvent {
  /// What happened.
  enum class Kind {
    KeyPress,       ///< key `code` (GLFW_KEY_*) went down (key repeats are not events)
    Character,      ///< character `code` (a Unicode code point) was typed
    ButtonPress,    ///< mouse button `code` (GLFW_MOUSE_BUTTON_*) went down
    ButtonRelease,  ///< mouse button `code` went up
    Drop,           ///< the file `path` was dropped on the window (one event per file)
  };
  Kind kind;         ///< what happened
  int code;          ///< the key, character or button (0 for a drop)
  int mods;          ///< GLFW_MOD_* bits held at the time (0 for characters and drops)
  std::string path;  ///< the dropped file (empty for the other kinds)
};

/// One frame of input. Installs key, character, mouse button, scroll and drop callbacks on the
/// window: create it before Dear ImGui installs its own, which then chain to these.
class InputTracker {
 public:
  /// Tracks `window` (its user pointer is set to this tracker).
  explicit InputTracker(GLFWwindow* window);
  /// Removes its callbacks from the window.
  ~InputTracker();
  InputTracker(const InputTracker&) = delete;
  InputTracker& operator=(const InputTracker&) = delete;

  /// Starts a frame: the events queued since the previous call become this frame's, the cursor is
  /// sampled. Call once a frame after glfwPollEvents().
  void sample();

  /// This frame's events, oldest first.
  const std::vector<InputEvent>& events() const { return events_; }
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
  /// True while mouse button `button` (GLFW_MOUSE_BUTTON_*) is down (after this frame's events).
  bool button(int button) const;
  /// True when key `key` (GLFW_KEY_*) is down after this frame's events, or went down during them.
  bool held(int key) const;

 private:
  static InputTracker& of(GLFWwindow* window);
  static void on_key(GLFWwindow* window, int key, int scancode, int action, int mods);
  static void on_char(GLFWwindow* window, unsigned int codepoint);
  static void on_mouse_button(GLFWwindow* window, int button, int action, int mods);
  static void on_scroll(GLFWwindow* window, double x, double y);
  static void on_drop(GLFWwindow* window, int count, const char** paths);

  GLFWwindow* window_;
  double x_ = 0, y_ = 0, previous_x_ = 0, previous_y_ = 0;
  double scroll_ = 0, pending_scroll_ = 0;
  std::vector<InputEvent> events_, pending_events_;
  std::array<bool, 512> keys_down_{}, keys_pressed_{}, keys_held_{};  // now, pressed since sample, this frame
  std::array<bool, 8> buttons_down_{}, buttons_held_{};               // now, this frame
};

}  // namespace viewer
