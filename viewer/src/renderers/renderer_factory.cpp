#include "renderers/renderer_factory.hpp"

#include "renderers/cube_renderer.hpp"
#include "renderers/marching_cubes_renderer.hpp"
#include "renderers/raymarch_renderer.hpp"

namespace viewer {

const char* to_string(RendererKind kind) {
  switch (kind) {
    case RendererKind::Cubes: return "cubes";
    case RendererKind::Marching: return "marching";
    case RendererKind::Raymarch: return "raymarch";
  }
  return "?";
}

std::unique_ptr<Renderer> make_renderer(RendererKind kind, const VulkanContext& context, const CellBuffer& cells,
                                        const MaterialPalette& palette, VkRenderPass target_pass,
                                        const RenderDetail& detail) {
  switch (kind) {
    case RendererKind::Cubes: return std::make_unique<CubeRenderer>(context, cells, palette, target_pass);
    case RendererKind::Marching: return std::make_unique<MarchingCubesRenderer>(context, cells, palette, target_pass, detail);
    case RendererKind::Raymarch: return std::make_unique<RaymarchRenderer>(context, cells, palette);
  }
  return nullptr;
}

std::optional<RendererKind> parse_renderer_kind(std::string_view name) {
  for (RendererKind kind : {RendererKind::Cubes, RendererKind::Marching, RendererKind::Raymarch})
    if (name == to_string(kind)) return kind;
  return std::nullopt;
}

}  // namespace viewer
