/// @file test_controls.cpp
/// The controls table (controls.hpp) and its dispatch: every row binds an input, no input is bound
/// twice, a row whose command has no handler is reported (the sandbox refuses to start then), and
/// key presses, characters, clicks, drags, the wheel and drops reach the commands the table names,
/// with the modifier rules of Binding. No window needed.

#include <doctest/doctest.h>

#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "window/control_dispatch.hpp"
#include "window/controls.hpp"
#include "window/input_tracker.hpp"

using namespace viewer;

namespace {

/// Every command that the table names.
std::set<Command> table_commands() {
  std::set<Command> commands;
  for (const Control& control : kControls)
    for (const Binding& binding : control.bindings)
      if (binding.trigger != Trigger::None) commands.insert(binding.command);
  return commands;
}

/// The commands (with their arguments) that one input triggers.
std::vector<std::pair<Command, int>> commands_of(Trigger trigger, int code, int mods = 0) {
  std::vector<std::pair<Command, int>> result;
  for (const Binding& binding : ControlDispatch::triggered(trigger, code, mods))
    result.emplace_back(binding.command, binding.argument);
  return result;
}

using Commands = std::vector<std::pair<Command, int>>;

}  // namespace

TEST_CASE("controls: every row of the table binds an input, and no input is bound twice") {
  std::set<std::tuple<Trigger, int, int>> inputs;
  for (const Control& control : kControls) {
    int bound = 0;
    for (const Binding& binding : control.bindings) {
      if (binding.trigger == Trigger::None) continue;
      ++bound;
      const bool first = inputs.emplace(binding.trigger, binding.code, binding.mods).second;
      INFO("row '" << control.text.input << "' binds an input that another binding has");
      CHECK(first);
    }
    INFO("row '" << control.text.input << "' has no binding");
    CHECK(bound > 0);
  }
}

TEST_CASE("controls: a row whose command has no handler is reported by its input text") {
  ControlDispatch dispatch;
  CHECK(dispatch.unhandled().size() == kControls.size());
  for (Command command : table_commands()) dispatch.handle(command, [](const Activation&) {});
  CHECK(dispatch.unhandled().empty());

  ControlDispatch without_redo;
  for (Command command : table_commands())
    if (command != Command::Redo) without_redo.handle(command, [](const Activation&) {});
  CHECK(without_redo.unhandled() == std::vector<std::string>{"Ctrl+Shift+Z, or Ctrl+Y"});

  ControlDispatch without_fly;
  for (Command command : table_commands())
    if (command != Command::Fly) without_fly.handle(command, [](const Activation&) {});
  CHECK(without_fly.unhandled() == std::vector<std::string>{"W A S D", "Q / E"});
}

TEST_CASE("controls: modifiers pick the binding; without Ctrl in the binding, Ctrl held stops it") {
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_Z, GLFW_MOD_CONTROL) == Commands{{Command::Undo, 0}});
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_Z, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT) == Commands{{Command::Redo, 0}});
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_Y, GLFW_MOD_CONTROL) == Commands{{Command::Redo, 0}});
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_Z).empty());  // Z alone zooms while held
  CHECK(commands_of(Trigger::KeyHeld, GLFW_KEY_Z) == Commands{{Command::Zoom, -1}});
  CHECK(commands_of(Trigger::KeyHeld, GLFW_KEY_Z, GLFW_MOD_CONTROL).empty());
  CHECK(commands_of(Trigger::KeyHeld, GLFW_KEY_S) == Commands{{Command::Fly, FlyBack}});
  CHECK(commands_of(Trigger::KeyHeld, GLFW_KEY_S, GLFW_MOD_CONTROL).empty());  // Ctrl+S saves
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_S, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT) == Commands{{Command::Save, 0}});
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_F, GLFW_MOD_SHIFT) == Commands{{Command::FrameContent, 0}});
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_F, GLFW_MOD_CONTROL).empty());
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_3) == Commands{{Command::ChooseMaterial, 3}});
  CHECK(commands_of(Trigger::KeyPress, GLFW_KEY_8).empty());
  CHECK(commands_of(Trigger::Character, '[') == Commands{{Command::ChangeTicks, -1}});
  CHECK(commands_of(Trigger::Character, '.') == Commands{{Command::MoveSection, +1}});
  CHECK(commands_of(Trigger::ButtonPress, GLFW_MOUSE_BUTTON_LEFT) == Commands{{Command::UseLeftTool, 0}});
  CHECK(commands_of(Trigger::ButtonPress, GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_ALT).empty());  // Alt + left orbits
  CHECK(commands_of(Trigger::ButtonDrag, GLFW_MOUSE_BUTTON_LEFT, GLFW_MOD_ALT) == Commands{{Command::Orbit, 0}});
  CHECK(commands_of(Trigger::ButtonDrag, GLFW_MOUSE_BUTTON_LEFT).empty());  // a plain left drag is a stroke
  CHECK(commands_of(Trigger::ButtonDrag, GLFW_MOUSE_BUTTON_MIDDLE) == Commands{{Command::Orbit, 0}});
  CHECK(commands_of(Trigger::ButtonDrag, GLFW_MOUSE_BUTTON_MIDDLE, GLFW_MOD_SHIFT) == Commands{{Command::Pan, 0}});
  CHECK(commands_of(Trigger::Wheel, 0) == Commands{{Command::BrushRadius, 0}});
  CHECK(commands_of(Trigger::Wheel, 0, GLFW_MOD_CONTROL) == Commands{{Command::WheelZoom, 0}});
}

TEST_CASE("controls: input events run the handlers of the commands their bindings name") {
  ControlDispatch dispatch;
  std::vector<std::pair<Command, int>> ran;
  std::string dropped;
  for (Command command : table_commands())
    dispatch.handle(command, [&ran, &dropped, command](const Activation& a) {
      ran.emplace_back(command, a.argument);
      if (!a.path.empty()) dropped = a.path;
    });
  dispatch.dispatch({InputEvent::Kind::KeyPress, GLFW_KEY_Z, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT, {}}, {});
  dispatch.dispatch({InputEvent::Kind::KeyPress, GLFW_KEY_5, 0, {}}, {});
  dispatch.dispatch({InputEvent::Kind::Character, ']', 0, {}}, {});
  dispatch.dispatch({InputEvent::Kind::ButtonPress, GLFW_MOUSE_BUTTON_RIGHT, 0, {}}, {});
  dispatch.dispatch({InputEvent::Kind::ButtonRelease, GLFW_MOUSE_BUTTON_RIGHT, 0, {}}, {});
  dispatch.dispatch({InputEvent::Kind::Drop, 0, 0, "world.gsnap"}, {});
  CHECK(ran == Commands{{Command::Redo, 0}, {Command::ChooseMaterial, 5}, {Command::ChangeTicks, +1},
                        {Command::UseRightTool, 0}, {Command::OpenDropped, 0}});
  CHECK(dropped == "world.gsnap");

  ran.clear();
  InputClaims hud;  // the HUD takes the keyboard and the mouse: keys and clicks are its own
  hud.keyboard = hud.mouse = true;
  dispatch.dispatch({InputEvent::Kind::KeyPress, GLFW_KEY_ESCAPE, 0, {}}, hud);
  dispatch.dispatch({InputEvent::Kind::Character, '[', 0, {}}, hud);
  dispatch.dispatch({InputEvent::Kind::ButtonPress, GLFW_MOUSE_BUTTON_LEFT, 0, {}}, hud);
  CHECK(ran.empty());
  dispatch.dispatch({InputEvent::Kind::Drop, 0, 0, "a.vox"}, hud);  // a drop is the window's, not the HUD's
  CHECK(ran == Commands{{Command::OpenDropped, 0}});
}
