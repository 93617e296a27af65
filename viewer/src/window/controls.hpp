#pragma once
/// @file controls.hpp
/// The sandbox's controls, as one table: each row's text (the HUD lists it, the README copies it)
/// and the inputs that trigger its commands. The sandbox's input handling dispatches through this
/// table (control_dispatch.hpp), so a key is bound exactly where it is described.

#include <array>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

namespace viewer {

/// What the sandbox does in answer to an input; each has one handler in the sandbox.
enum class Command {
  UseLeftTool,     ///< start a stroke of the left button's tool
  UseRightTool,    ///< start a stroke pouring or painting the chosen material
  BrushRadius,     ///< change the brush radius by the wheel's steps
  Orbit,           ///< turn the camera around its target by the drag
  Pan,             ///< move the camera's target across the view by the drag
  Zoom,            ///< held: zoom in (argument -1) or out (+1) for the frame's time
  WheelZoom,       ///< zoom by the wheel's steps
  Fly,             ///< held: move the camera along the argument's FlyDirection for the frame's time
  FrameContent,    ///< frame every non-void cell
  CycleLeftTool,   ///< the left button's next tool
  ChooseMaterial,  ///< the material of state `argument` for the right button
#ifdef GRANULAR_SANDBOX_BODIES
  ThrowBody,       ///< throw the HUD's body from the camera along the cursor's ray (built with Bullet)
#endif
  PauseResume,     ///< pause or resume the simulation
  Step,            ///< one fixed update while paused
  ChangeTicks,     ///< ticks per fixed update by `argument` (-1 or +1)
  NextRenderer,    ///< the next renderer
  CycleSection,    ///< the section plane's next axis (or off)
  MoveSection,     ///< the section plane by `argument` (-1 or +1) steps
  XRay,            ///< static materials translucent, or opaque again
  Screenshot,      ///< the frame to the next free screenshot file
  Reset,           ///< the scene again
  Undo,            ///< undo the last stroke
  Redo,            ///< redo the stroke undone last
  Save,            ///< write the snapshot file
  Load,            ///< load the snapshot file
  OpenDropped,     ///< load the world file dropped on the window
  Quit,            ///< close the window
};

/// Where a Command::Fly binding moves the camera (its argument).
enum FlyDirection : int { FlyForward, FlyBack, FlyLeft, FlyRight, FlyDown, FlyUp };

/// How an input triggers a command.
enum class Trigger {
  None,         ///< an unused slot of a row's bindings
  KeyPress,     ///< key `code` (GLFW_KEY_*) goes down: acts once
  KeyHeld,      ///< key `code` is down: acts every frame, for the frame's time
  Character,    ///< character `code` is typed (whatever key and modifiers type it): acts once
  ButtonPress,  ///< mouse button `code` (GLFW_MOUSE_BUTTON_*) goes down: acts once
  ButtonDrag,   ///< mouse button `code` is down: acts every frame, for the cursor's motion
  Wheel,        ///< the wheel turns: acts every frame it turns, for its steps
  Drop,         ///< a file is dropped on the window: acts once per file
};

/// One input and the command it triggers. `mods` (GLFW_MOD_CONTROL, _SHIFT, _ALT) must be held; of
/// the bindings of one key or button whose modifiers are held, the one with the most acts, and a
/// binding without Ctrl never acts while Ctrl is held (Ctrl + key is a command of its own).
struct Binding {
  Trigger trigger = Trigger::None;  ///< how the input triggers it
  int code = 0;                     ///< the key, character or button (0 for the wheel and drops)
  int mods = 0;                     ///< the modifiers it needs
  Command command = Command::Quit;  ///< what it does
  int argument = 0;                 ///< what the command is given (a material's state, a direction)
};

/// A key press of `key` with `mods` held.
constexpr Binding press(int key, Command command, int mods = 0, int argument = 0) {
  return {Trigger::KeyPress, key, mods, command, argument};
}
/// Key `key` held (no Ctrl).
constexpr Binding hold(int key, Command command, int argument) { return {Trigger::KeyHeld, key, 0, command, argument}; }
/// The character `character` typed.
constexpr Binding type(int character, Command command, int argument) {
  return {Trigger::Character, character, 0, command, argument};
}
/// A press of mouse button `button`.
constexpr Binding click(int button, Command command) { return {Trigger::ButtonPress, button, 0, command, 0}; }
/// A drag with mouse button `button` and `mods` held.
constexpr Binding drag(int button, Command command, int mods = 0) { return {Trigger::ButtonDrag, button, mods, command, 0}; }
/// The wheel turned with `mods` held.
constexpr Binding wheel(Command command, int mods = 0) { return {Trigger::Wheel, 0, mods, command, 0}; }

/// The most bindings one row has (keys 1..7).
inline constexpr int kMaxBindings = 7;

/// A row's text: the input and what it does, as the HUD and the README show them.
struct ControlText {
  const char* input;   ///< key or mouse gesture
  const char* action;  ///< what it does
};

/// One control: its text and the bindings that do what the text says (unused slots: Trigger::None).
struct Control {
  ControlText text;                             ///< what the HUD and README say
  std::array<Binding, kMaxBindings> bindings;  ///< the inputs and the commands they trigger
};

/// Whether this sandbox throws bodies: built with Bullet (granular::bullet), which moves them. Without
/// it the table has no throw row and the HUD no bodies section.
#ifdef GRANULAR_SANDBOX_BODIES
inline constexpr bool kThrowsBodies = true;
#else
inline constexpr bool kThrowsBodies = false;
#endif

/// Every control of the windowed sandbox.
inline constexpr std::array<Control, 26 + (kThrowsBodies ? 1 : 0)> kControls{{
    {{"left button", "dig (removes every mobile material: granular, liquid, gas; static ones stay) / erase (removes everything) / shake (sets the grains and liquids moving at the rules' highest motion level) where the cursor's ray hits"},
     {click(GLFW_MOUSE_BUTTON_LEFT, Command::UseLeftTool)}},
    {{"right button", "the chosen material: pour it above the hit point (granular, liquid, gas) / paint it as a sphere of structure in front of the hit face (static)"},
     {click(GLFW_MOUSE_BUTTON_RIGHT, Command::UseRightTool)}},
    {{"wheel", "brush radius"}, {wheel(Command::BrushRadius)}},
    {{"middle drag, or Alt + left drag", "orbit"},
     {drag(GLFW_MOUSE_BUTTON_MIDDLE, Command::Orbit), drag(GLFW_MOUSE_BUTTON_LEFT, Command::Orbit, GLFW_MOD_ALT)}},
    {{"Shift + middle drag", "pan"}, {drag(GLFW_MOUSE_BUTTON_MIDDLE, Command::Pan, GLFW_MOD_SHIFT)}},
    {{"Ctrl + wheel, or Z / X", "zoom in / out"},
     {wheel(Command::WheelZoom, GLFW_MOD_CONTROL), hold(GLFW_KEY_Z, Command::Zoom, -1), hold(GLFW_KEY_X, Command::Zoom, +1)}},
    {{"W A S D", "fly forward / left / back / right"},
     {hold(GLFW_KEY_W, Command::Fly, FlyForward), hold(GLFW_KEY_A, Command::Fly, FlyLeft),
      hold(GLFW_KEY_S, Command::Fly, FlyBack), hold(GLFW_KEY_D, Command::Fly, FlyRight)}},
    {{"Q / E", "fly down / up"}, {hold(GLFW_KEY_Q, Command::Fly, FlyDown), hold(GLFW_KEY_E, Command::Fly, FlyUp)}},
    {{"F", "frame the content (every non-void cell, as at the start)"}, {press(GLFW_KEY_F, Command::FrameContent)}},
    {{"Tab", "cycle the left button: dig / erase / shake (shake only under rules with a motion model, as the default inertial-24-flow; one-step rules such as paper have none)"},
     {press(GLFW_KEY_TAB, Command::CycleLeftTool)}},
    {{"1 .. 7", "choose the material of state 1..7 of the world's table (the HUD lists each with its colour; presets: solid, granular, liquid, gas, gravel, state6, state7)"},
     {press(GLFW_KEY_1, Command::ChooseMaterial, 0, 1), press(GLFW_KEY_2, Command::ChooseMaterial, 0, 2),
      press(GLFW_KEY_3, Command::ChooseMaterial, 0, 3), press(GLFW_KEY_4, Command::ChooseMaterial, 0, 4),
      press(GLFW_KEY_5, Command::ChooseMaterial, 0, 5), press(GLFW_KEY_6, Command::ChooseMaterial, 0, 6),
      press(GLFW_KEY_7, Command::ChooseMaterial, 0, 7)}},
#ifdef GRANULAR_SANDBOX_BODIES
    {{"T", "throw a body (sandboxes built with Bullet): the HUD's ball or box, size and density, from just in front of the camera along the cursor's ray; it falls, lands, and floats or sinks by its density (drawn in the body material's colour, state7 in the presets)"},
     {press(GLFW_KEY_T, Command::ThrowBody)}},
#endif
    {{"Space", "pause / resume"}, {press(GLFW_KEY_SPACE, Command::PauseResume)}},
    {{"N", "single step (while paused)"}, {press(GLFW_KEY_N, Command::Step)}},
    {{"[ / ]", "fewer / more ticks per fixed update"},
     {type('[', Command::ChangeTicks, -1), type(']', Command::ChangeTicks, +1)}},
    {{"C", "next renderer (cubes, marching, raymarch)"}, {press(GLFW_KEY_C, Command::NextRenderer)}},
    {{"V", "section plane: off / across x / y / z (removes the cells between the camera and the plane, so the cut shows the inside)"},
     {press(GLFW_KEY_V, Command::CycleSection)}},
    {{", / .", "move the section plane 1/32 of its axis towards lower / higher coordinates"},
     {type(',', Command::MoveSection, -1), type('.', Command::MoveSection, +1)}},
    {{"B", "x-ray: draw static materials translucent, to see what a container holds"}, {press(GLFW_KEY_B, Command::XRay)}},
    {{"P", "screenshot: the current frame to granular-screenshot-N.png (N: the first free number)"},
     {press(GLFW_KEY_P, Command::Screenshot)}},
    {{"R", "reset the scene"}, {press(GLFW_KEY_R, Command::Reset)}},
    {{"Ctrl+Z", "undo the last stroke (a tool from press to release, or a throw): the world as it was when the stroke began, ticks since included; then pauses"},
     {press(GLFW_KEY_Z, Command::Undo, GLFW_MOD_CONTROL)}},
    {{"Ctrl+Shift+Z, or Ctrl+Y", "redo: the world as it was when the stroke ended (while nothing changed since the undo)"},
     {press(GLFW_KEY_Z, Command::Redo, GLFW_MOD_CONTROL | GLFW_MOD_SHIFT), press(GLFW_KEY_Y, Command::Redo, GLFW_MOD_CONTROL)}},
    {{"Ctrl+S", "save a snapshot of the world to the snapshot file (--save, default granular-sandbox.gsnap)"},
     {press(GLFW_KEY_S, Command::Save, GLFW_MOD_CONTROL)}},
    {{"Ctrl+O", "load the snapshot file"}, {press(GLFW_KEY_O, Command::Load, GLFW_MOD_CONTROL)}},
    {{"drop a file", "load a .gsnap snapshot, or a .raw or .vox grid, dropped on the window"},
     {{Trigger::Drop, 0, 0, Command::OpenDropped, 0}}},
    {{"Esc", "quit"}, {press(GLFW_KEY_ESCAPE, Command::Quit)}},
}};

}  // namespace viewer
