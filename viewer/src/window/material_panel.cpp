#include "window/material_panel.hpp"

#include <cstdio>
#include <string>

#include <imgui.h>

#include "granular/rule_set.hpp"
#include "cells/material_palette.hpp"

namespace viewer {

std::optional<granular::Material> draw_material_panel(const std::vector<MaterialChoice>& choices, granular::Material chosen,
                                                      const granular::MaterialCounts& counts) {
  std::optional<granular::Material> clicked;
  char row[160];
  ImGui::Indent(kSwatchSize + ImGui::GetStyle().ItemSpacing.x);
  std::snprintf(row, sizeof(row), "%-4s%-10s %-9s %-5s %10s", "key", "material", "behaviour", "right", "cells");
  ImGui::TextDisabled("%s", row);
  ImGui::Unindent(kSwatchSize + ImGui::GetStyle().ItemSpacing.x);
  for (const MaterialChoice& choice : choices) {
    ImGui::PushID(choice.key);
    const glm::vec3 rgb = colour_of(choice.colour);
    const ImVec4 colour(rgb.r, rgb.g, rgb.b, 1.0f);
    ImGui::ColorButton("##swatch", colour, ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoPicker,
                       ImVec2(kSwatchSize, kSwatchSize));
    ImGui::SameLine();
    std::snprintf(row, sizeof(row), "%-4d%-10s %-9s %-5s %10llu", choice.key, choice.name.c_str(),
                  granular::behaviour_name(choice.behaviour), to_string(choice.use),
                  static_cast<unsigned long long>(counts[std::size_t(choice.key)]));
    if (ImGui::Selectable(row, choice.material == chosen)) clicked = choice.material;
    ImGui::PopID();
  }
  return clicked;
}

}  // namespace viewer
