#pragma once
/// @file control_dispatch.hpp
/// The sandbox's input, dispatched through the controls table (controls.hpp): each input event,
/// held key, drag and wheel turn runs the handler of the command its binding names.

#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "window/controls.hpp"

namespace viewer {

struct InputEvent;
class InputTracker;

/// What a handler is given when its binding acts.
struct Activation {
  int argument = 0;       ///< the binding's argument (a material's state, a direction, a step)
  double seconds = 0;     ///< held keys: the frame's time
  double dx = 0, dy = 0;  ///< drags: the cursor's motion since the last frame, in pixels
  double steps = 0;       ///< the wheel: its steps (positive: away from the user)
  std::string_view path;  ///< drops: the dropped file
};

/// Which inputs this frame's dispatch leaves alone.
struct InputClaims {
  bool keyboard = false;  ///< the HUD takes the keyboard (key presses, characters, held keys)
  bool mouse = false;     ///< the HUD takes the mouse (clicks, drags, the wheel)
  int stroke_button = -1;  ///< the mouse button holding a stroke (its drag is the stroke's), -1 for none
};

/// The handlers of the commands and the dispatch of input to them through kControls.
class ControlDispatch {
 public:
  /// What a command does.
  using Handler = std::function<void(const Activation&)>;

  /// Makes `handler` what `command` does (replacing an earlier one).
  void handle(Command command, Handler handler);

  /// The input text of every row of kControls with a command that has no handler, in table order;
  /// empty when every row is served.
  std::vector<std::string> unhandled() const;

  /// Runs the handlers of the bindings that `event` (a key press, character, button press or drop)
  /// triggers, unless `claims` leaves that input to the HUD; a button release triggers none.
  void dispatch(const InputEvent& event, const InputClaims& claims) const;

  /// Runs the handlers of the held keys, drags and wheel turns of `input`'s frame of `seconds`.
  void dispatch_held(const InputTracker& input, double seconds, const InputClaims& claims) const;

  /// The bindings of kControls that an input of `trigger` on `code` with modifiers `mods` held
  /// triggers (see Binding for the modifier rules).
  static std::vector<Binding> triggered(Trigger trigger, int code, int mods);

 private:
  void run(const Binding& binding, const Activation& activation) const;

  std::map<Command, Handler> handlers_;
};

}  // namespace viewer
