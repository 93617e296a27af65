#pragma once
/// @file material_palette.hpp
/// The world's material table as the viewer's shaders read it (shaders/materials.glsl): for each
/// cell state its display colour (granular::MaterialDef::colour) and its look, how the renderers
/// draw it, in one small uniform buffer that every renderer binds. A game's own material shows in
/// its own colour with no shader change.

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

#include "vulkan/gpu_buffer.hpp"
#include "granular/rule_set.hpp"

namespace viewer {

class VulkanContext;

/// How the renderers draw a material (mirrors the kLook* constants of shaders/materials.glsl).
enum class MaterialLook : std::uint32_t {
  Void = 0,    ///< not drawn
  Opaque = 1,  ///< static and granular materials: opaque, with a per-cell brightness jitter
  Liquid = 2,  ///< translucent, smooth, with a sun glint
  Gas = 3,     ///< faint, smooth
};

/// The look of a material of behaviour `behaviour`.
MaterialLook look_of(granular::Behaviour behaviour);

/// A display colour 0xRRGGBB as red, green, blue in 0..1 (the value the shaders write for it on a
/// surface lit head-on by the sun).
glm::vec3 colour_of(std::uint32_t rgb);

/// One state's entry of the buffer, in the shaders' std140 layout.
struct PaletteEntry {
  glm::vec4 colour{0.0f};  ///< rgb: colour_of(MaterialDef::colour); a: unused
  glm::uvec4 look{0u};     ///< x: the MaterialLook; y: 1 for a static material (x-ray draws it translucent); zw: unused
};
static_assert(sizeof(PaletteEntry) == 32);

/// The buffer's contents for `table`: entry s describes cell state s.
std::array<PaletteEntry, granular::kMaterialCount> palette_entries(const granular::MaterialTable& table);

/// The uniform buffer of a material table (host-visible, written once).
class MaterialPalette {
 public:
  /// Fills the buffer from `table`.
  MaterialPalette(const VulkanContext& context, const granular::MaterialTable& table);
  /// The uniform buffer (binding it is the renderers' business).
  VkBuffer buffer() const { return buffer_.buffer(); }

 private:
  GpuBuffer buffer_;
};

}  // namespace viewer
