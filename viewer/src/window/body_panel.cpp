#include "window/body_panel.hpp"

#include <imgui.h>

#include "cells/material_palette.hpp"
#include "window/material_panel.hpp"

namespace viewer {

void draw_body_panel(ThrowChoice& choice, std::size_t bodies, const granular::MaterialDef& body_material) {
  ImGui::Separator();
  const glm::vec3 rgb = colour_of(body_material.colour);
  ImGui::ColorButton("##body-swatch", ImVec4(rgb.r, rgb.g, rgb.b, 1.0f),
                     ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoPicker, ImVec2(kSwatchSize, kSwatchSize));
  ImGui::SameLine();
  ImGui::Text("bodies: %zu of %zu (T throws one; drawn as %s)", bodies, kMaxSandboxBodies, body_material.name.c_str());
  if (ImGui::RadioButton("ball", choice.shape == granular::BodyShape::Sphere))
    choice.shape = granular::BodyShape::Sphere;
  ImGui::SameLine();
  if (ImGui::RadioButton("box", choice.shape == granular::BodyShape::Box)) choice.shape = granular::BodyShape::Box;
  // No Ctrl+click text entry: the sliders give only values within their ranges.
  int half = int(choice.half_size);
  if (ImGui::SliderInt("half size (cells)", &half, int(kMinThrowHalfSize), int(kMaxThrowHalfSize), "%d",
                       ImGuiSliderFlags_NoInput))
    choice.half_size = half;
  float density = float(choice.density);
  if (ImGui::SliderFloat("density (kg/m^3)", &density, float(kMinThrowDensity), float(kMaxThrowDensity), "%.0f",
                         ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoInput))
    choice.density = density;
  ImGui::TextDisabled("%.0f kg/m^3 %s", choice.density, density_effect(choice.density).c_str());
}

}  // namespace viewer
