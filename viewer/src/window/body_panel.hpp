#pragma once
/// @file body_panel.hpp
/// The HUD's bodies section (sandboxes built with Bullet): the shape, size and density of the body
/// key T throws next, what that density does in sand and water, how many bodies there are of the
/// sandbox's most, and the colour they are drawn in (the body material's). Drawn with Dear ImGui
/// between Hud::begin() and Hud::record().

#include <cstddef>

#include "bodies/body_throw.hpp"
#include "granular/rule_set.hpp"

namespace viewer {

/// Draws the section into the current ImGui window; the widgets change `choice` (within its ranges).
/// `bodies` is how many there are; `body_material` the World's body material (WorldDef::body_material).
void draw_body_panel(ThrowChoice& choice, std::size_t bodies, const granular::MaterialDef& body_material);

}  // namespace viewer
