#include "cells/material_palette.hpp"

#include <cstring>

namespace viewer {

MaterialLook look_of(granular::Behaviour behaviour) {
  switch (behaviour) {
    case granular::Behaviour::Void: return MaterialLook::Void;
    case granular::Behaviour::Static:
    case granular::Behaviour::Granular: return MaterialLook::Opaque;
    case granular::Behaviour::Liquid: return MaterialLook::Liquid;
    case granular::Behaviour::Gas: return MaterialLook::Gas;
  }
  return MaterialLook::Opaque;
}

glm::vec3 colour_of(std::uint32_t rgb) {
  return glm::vec3(float((rgb >> 16) & 0xFF), float((rgb >> 8) & 0xFF), float(rgb & 0xFF)) / 255.0f;
}

std::array<PaletteEntry, granular::kMaterialCount> palette_entries(const granular::MaterialTable& table) {
  std::array<PaletteEntry, granular::kMaterialCount> entries{};
  for (std::size_t s = 0; s < entries.size(); ++s) {
    entries[s].colour = glm::vec4(colour_of(table[s].colour), 1.0f);
    entries[s].look.x = std::uint32_t(look_of(table[s].behaviour));
    entries[s].look.y = table[s].behaviour == granular::Behaviour::Static ? 1u : 0u;
  }
  return entries;
}

MaterialPalette::MaterialPalette(const VulkanContext& context, const granular::MaterialTable& table)
    : buffer_(context, sizeof(PaletteEntry) * granular::kMaterialCount, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
              MemoryKind::HostVisible) {
  const auto entries = palette_entries(table);
  std::memcpy(buffer_.mapped(), entries.data(), sizeof(entries));
}

}  // namespace viewer
