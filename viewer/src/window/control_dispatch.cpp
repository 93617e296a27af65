#include "window/control_dispatch.hpp"

#include <algorithm>
#include <bit>
#include <utility>

#include "window/input_tracker.hpp"

namespace viewer {
namespace {

constexpr int kModifiers = GLFW_MOD_CONTROL | GLFW_MOD_SHIFT | GLFW_MOD_ALT;

/// The input a trigger listens to: a key's press and hold are one key, a button's press and drag one button.
enum class Device { None, Key, Character, Button, Wheel, Drop };

Device device_of(Trigger trigger) {
  switch (trigger) {
    case Trigger::KeyPress:
    case Trigger::KeyHeld: return Device::Key;
    case Trigger::Character: return Device::Character;
    case Trigger::ButtonPress:
    case Trigger::ButtonDrag: return Device::Button;
    case Trigger::Wheel: return Device::Wheel;
    case Trigger::Drop: return Device::Drop;
    case Trigger::None: break;
  }
  return Device::None;
}

/// True when a binding that needs `required` may act with `held` held: all of them held, and Ctrl
/// held only when it needs Ctrl.
bool modifiers_fit(int required, int held) {
  return (required & held) == required && ((required ^ held) & GLFW_MOD_CONTROL) == 0;
}

/// The modifiers held now, from the tracker's keys.
int held_modifiers(const InputTracker& input) {
  int mods = 0;
  if (input.held(GLFW_KEY_LEFT_CONTROL) || input.held(GLFW_KEY_RIGHT_CONTROL)) mods |= GLFW_MOD_CONTROL;
  if (input.held(GLFW_KEY_LEFT_SHIFT) || input.held(GLFW_KEY_RIGHT_SHIFT)) mods |= GLFW_MOD_SHIFT;
  if (input.held(GLFW_KEY_LEFT_ALT) || input.held(GLFW_KEY_RIGHT_ALT)) mods |= GLFW_MOD_ALT;
  return mods;
}

}  // namespace

void ControlDispatch::handle(Command command, Handler handler) { handlers_[command] = std::move(handler); }

std::vector<std::string> ControlDispatch::unhandled() const {
  std::vector<std::string> rows;
  for (const Control& control : kControls)
    for (const Binding& binding : control.bindings)
      if (binding.trigger != Trigger::None && !handlers_.contains(binding.command)) {
        rows.emplace_back(control.text.input);
        break;
      }
  return rows;
}

std::vector<Binding> ControlDispatch::triggered(Trigger trigger, int code, int mods) {
  const Device device = device_of(trigger);
  const int held = device == Device::Character || device == Device::Drop ? 0 : mods & kModifiers;
  // Of the fitting bindings on this key or button, those needing the most modifiers act.
  int most = -1;
  for (const Control& control : kControls)
    for (const Binding& binding : control.bindings)
      if (device_of(binding.trigger) == device && binding.code == code && modifiers_fit(binding.mods, held))
        most = std::max(most, std::popcount(unsigned(binding.mods)));
  std::vector<Binding> result;
  for (const Control& control : kControls)
    for (const Binding& binding : control.bindings)
      if (binding.trigger == trigger && binding.code == code && modifiers_fit(binding.mods, held) &&
          std::popcount(unsigned(binding.mods)) == most)
        result.push_back(binding);
  return result;
}

void ControlDispatch::dispatch(const InputEvent& event, const InputClaims& claims) const {
  Trigger trigger = Trigger::None;
  switch (event.kind) {
    case InputEvent::Kind::KeyPress: trigger = claims.keyboard ? Trigger::None : Trigger::KeyPress; break;
    case InputEvent::Kind::Character: trigger = claims.keyboard ? Trigger::None : Trigger::Character; break;
    case InputEvent::Kind::ButtonPress: trigger = claims.mouse ? Trigger::None : Trigger::ButtonPress; break;
    case InputEvent::Kind::Drop: trigger = Trigger::Drop; break;
    case InputEvent::Kind::ButtonRelease: break;
  }
  if (trigger == Trigger::None) return;
  for (const Binding& binding : triggered(trigger, event.code, event.mods)) {
    Activation activation;
    activation.argument = binding.argument;
    activation.path = event.path;
    run(binding, activation);
  }
}

void ControlDispatch::dispatch_held(const InputTracker& input, double seconds, const InputClaims& claims) const {
  const int mods = held_modifiers(input);
  for (const Control& control : kControls)
    for (const Binding& binding : control.bindings) {
      Activation activation;
      activation.argument = binding.argument;
      if (binding.trigger == Trigger::KeyHeld && !claims.keyboard && input.held(binding.code)) {
        activation.seconds = seconds;
      } else if (binding.trigger == Trigger::ButtonDrag && !claims.mouse && binding.code != claims.stroke_button &&
                 input.button(binding.code)) {
        activation.dx = input.dx();
        activation.dy = input.dy();
      } else if (binding.trigger == Trigger::Wheel && !claims.mouse && input.scroll() != 0) {
        activation.steps = input.scroll();
      } else {
        continue;
      }
      for (const Binding& acting : triggered(binding.trigger, binding.code, mods))
        if (acting.command == binding.command && acting.argument == binding.argument) run(binding, activation);
    }
}

void ControlDispatch::run(const Binding& binding, const Activation& activation) const {
  const auto handler = handlers_.find(binding.command);
  if (handler != handlers_.end()) handler->second(activation);
}

}  // namespace viewer
