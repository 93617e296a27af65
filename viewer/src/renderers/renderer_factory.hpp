#pragma once
/// @file renderer_factory.hpp
/// Creates a renderer by kind and names the kinds; the one place a new renderer is registered.

#include <memory>
#include <optional>
#include <string_view>

#include "renderers/renderer.hpp"

namespace viewer {

class VulkanContext;
class CellBuffer;
class MaterialPalette;

/// A renderer of `kind` reading `cells` in the colours of `palette` (both must outlive it), drawing
/// into passes compatible with `target_pass`, keeping `detail`.
std::unique_ptr<Renderer> make_renderer(RendererKind kind, const VulkanContext& context, const CellBuffer& cells,
                                        const MaterialPalette& palette, VkRenderPass target_pass,
                                        const RenderDetail& detail);

/// The kind named `name` ("cubes", "marching", "raymarch"), or nothing.
std::optional<RendererKind> parse_renderer_kind(std::string_view name);

}  // namespace viewer
