#pragma once
/// @file controls.hpp
/// The sandbox's controls, as one table: the HUD lists it and the README copies it.

#include <array>

namespace viewer {

/// One control: the input and what it does.
struct Control {
  const char* input;   ///< key or mouse gesture
  const char* action;  ///< what it does
};

/// Every control of the windowed sandbox.
inline constexpr std::array<Control, 26> kControls{{
    {"left button", "dig (removes every mobile material: granular, liquid, gas; static ones stay) / erase (removes everything) / shake (sets the grains and liquids moving at the rules' highest motion level) where the cursor's ray hits"},
    {"right button", "the chosen material: pour it above the hit point (granular, liquid, gas) / paint it as a sphere of structure in front of the hit face (static)"},
    {"wheel", "brush radius"},
    {"middle drag, or Alt + left drag", "orbit"},
    {"Shift + middle drag", "pan"},
    {"Ctrl + wheel, or Z / X", "zoom in / out"},
    {"W A S D", "fly forward / left / back / right"},
    {"Q / E", "fly down / up"},
    {"F", "frame the content (every non-void cell, as at the start)"},
    {"Tab", "cycle the left button: dig / erase / shake (shake only under rules with a motion model, as the default inertial-24-flow; one-step rules such as paper have none)"},
    {"1 .. 7", "choose the material of state 1..7 of the world's table (the HUD lists each with its colour; presets: solid, granular, liquid, gas, gravel, state6, state7)"},
    {"Space", "pause / resume"},
    {"N", "single step (while paused)"},
    {"[ / ]", "fewer / more ticks per fixed update"},
    {"C", "next renderer (cubes, marching, raymarch)"},
    {"V", "section plane: off / across x / y / z (removes the cells between the camera and the plane, so the cut shows the inside)"},
    {", / .", "move the section plane 1/32 of its axis towards lower / higher coordinates"},
    {"B", "x-ray: draw static materials translucent, to see what a container holds"},
    {"P", "screenshot: the current frame to granular-screenshot-N.png (N: the first free number)"},
    {"R", "reset the scene"},
    {"Ctrl+Z", "undo the last stroke (a tool from press to release): the world as it was when the stroke began, ticks since included; then pauses"},
    {"Ctrl+Shift+Z, or Ctrl+Y", "redo: the world as it was when the stroke ended (while nothing changed since the undo)"},
    {"Ctrl+S", "save a snapshot of the world to the snapshot file (--save, default granular-sandbox.gsnap)"},
    {"Ctrl+O", "load the snapshot file"},
    {"drop a file", "load a .gsnap snapshot, or a .raw or .vox grid, dropped on the window"},
    {"Esc", "quit"},
}};

}  // namespace viewer
