#include "granular/material.hpp"

namespace granular {

namespace {
constexpr std::array<std::string_view, kMaterialCount> kNames = {"void",   "solid",  "granular", "liquid",
                                                                 "gas",    "gravel", "state6",   "state7"};
}

std::string_view material_name(Material m) noexcept {
  const auto v = static_cast<unsigned>(m);
  return v < kNames.size() ? kNames[v] : std::string_view("invalid");
}

std::optional<Material> parse_material(std::string_view name) noexcept {
  for (unsigned i = 0; i < kNames.size(); ++i)
    if (kNames[i] == name) return Material(i);
  if (name == "sand") return Material::Granular;
  if (name == "water") return Material::Liquid;
  return std::nullopt;
}

}  // namespace granular
