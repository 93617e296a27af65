#pragma once
/// @file material_panel.hpp
/// The HUD's list of the materials the sandbox offers (material_choices.hpp): one row per choice
/// with its colour swatch, number key, name, behaviour, what the right button does with it and its
/// cell count; the chosen one highlighted. Drawn with Dear ImGui between Hud::begin() and
/// Hud::record().

#include <optional>
#include <vector>

#include "granular/material.hpp"
#include "session/material_choices.hpp"

namespace viewer {

/// Side of a row's colour swatch, in pixels.
inline constexpr float kSwatchSize = 14.0f;

/// Draws a header and the rows of `choices` into the current ImGui window, `chosen` highlighted,
/// with the cell counts of `counts`. Returns the state whose row was clicked this frame, if any.
std::optional<granular::Material> draw_material_panel(const std::vector<MaterialChoice>& choices, granular::Material chosen,
                                                      const granular::MaterialCounts& counts);

}  // namespace viewer
