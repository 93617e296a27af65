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
inline constexpr std::array<Control, 17> kControls{{
    {"left button", "dig (sand brush) / erase (solid brush) where the cursor's ray hits"},
    {"right button", "pour the chosen material above the hit point (sand brush) / place solid (solid brush)"},
    {"wheel", "brush radius"},
    {"middle drag, or Alt + left drag", "orbit"},
    {"Shift + middle drag", "pan"},
    {"Ctrl + wheel, or Z / X", "zoom in / out"},
    {"W A S D", "fly forward / left / back / right"},
    {"Q / E", "fly down / up"},
    {"F", "frame the content (every non-void cell, as at the start)"},
    {"Tab", "switch brush: sand (dig, pour) / solid (erase, place)"},
    {"1 / 2 / 3", "pour material: granular / liquid / gas"},
    {"Space", "pause / resume"},
    {"N", "single step (while paused)"},
    {"[ / ]", "fewer / more ticks per fixed update"},
    {"C", "next renderer (cubes, marching, raymarch)"},
    {"R", "reset the scene"},
    {"Esc", "quit"},
}};

}  // namespace viewer
