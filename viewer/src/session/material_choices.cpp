#include "session/material_choices.hpp"

#include <cstdio>
#include <stdexcept>

namespace viewer {

const char* to_string(MaterialUse use) { return use == MaterialUse::Paint ? "paint" : "pour"; }

MaterialUse use_of(granular::Behaviour behaviour) {
  return behaviour == granular::Behaviour::Static ? MaterialUse::Paint : MaterialUse::Pour;
}

std::vector<MaterialChoice> material_choices(const granular::MaterialTable& table) {
  std::vector<MaterialChoice> choices;
  for (int s = 1; s < granular::kMaterialCount; ++s) {
    const granular::MaterialDef& def = table[std::size_t(s)];
    if (def.behaviour == granular::Behaviour::Void) continue;
    choices.push_back({s, granular::Material(s), def.name, def.colour, def.behaviour, use_of(def.behaviour)});
  }
  return choices;
}

std::optional<MaterialChoice> choice_of_key(const std::vector<MaterialChoice>& choices, int digit) {
  for (const MaterialChoice& choice : choices)
    if (choice.key == digit) return choice;
  return std::nullopt;
}

const MaterialChoice& choice_of(const std::vector<MaterialChoice>& choices, granular::Material material) {
  for (const MaterialChoice& choice : choices)
    if (choice.material == material) return choice;
  throw std::invalid_argument("state " + std::to_string(int(material)) + " is not a material the sandbox offers");
}

std::string describe(const std::vector<MaterialChoice>& choices) {
  std::string text;
  for (const MaterialChoice& choice : choices) {
    if (!text.empty()) text += ", ";
    char colour[8];
    std::snprintf(colour, sizeof(colour), "#%06X", unsigned(choice.colour & 0xFFFFFF));
    text += std::to_string(choice.key) + " " + choice.name + " " + colour;
  }
  return text;
}

}  // namespace viewer
