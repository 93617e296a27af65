#pragma once
/// @file pipeline_builder.hpp
/// Descriptor sets (one per frame slot) and compute / graphics pipelines over them, all using the
/// ViewConstants push constants.

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vulkan/frames_in_flight.hpp"

namespace viewer {

/// One descriptor set layout with a set per frame slot.
class DescriptorSets {
 public:
  /// Bindings 0..types.size()-1 of the given types, visible to every shader stage.
  DescriptorSets(VkDevice device, const std::vector<VkDescriptorType>& types);
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~DescriptorSets();
  DescriptorSets(const DescriptorSets&) = delete;
  DescriptorSets& operator=(const DescriptorSets&) = delete;

  /// The layout.
  VkDescriptorSetLayout layout() const { return layout_; }
  /// The set of frame slot `slot`.
  VkDescriptorSet set(int slot) const { return sets_[slot]; }
  /// Points `binding` of every slot's set at the whole of `buffer` (a storage or uniform buffer, as
  /// the binding's type says).
  void write_buffer(int binding, VkBuffer buffer);
  /// Points `binding` of slot `slot`'s set at the whole of `buffer` (a storage or uniform buffer, as
  /// the binding's type says).
  void write_buffer(int slot, int binding, VkBuffer buffer);
  /// Points `binding` of every slot's set at `view`, a storage image in GENERAL layout.
  void write_storage_image(int binding, VkImageView view);

 private:
  VkDevice device_;
  std::vector<VkDescriptorType> types_;
  VkDescriptorSetLayout layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::array<VkDescriptorSet, kFramesInFlight> sets_{};
};

/// How a graphics pipeline rasterises.
struct GraphicsOptions {
  VkCullModeFlags cull = VK_CULL_MODE_BACK_BIT;  ///< faces culled
  bool blend = false;        ///< blend the fragment's colour over the target's by its alpha (the target keeps its alpha)
  bool depth_write = true;   ///< write depth (off for translucent surfaces, which are depth-tested only)

  /// The options of a translucent surface's pipeline: blended, depth-tested but not written.
  static GraphicsOptions translucent() {
    GraphicsOptions options;
    options.blend = true;
    options.depth_write = false;
    return options;
  }
};

/// `storage` storage buffers at bindings 0 .. storage - 1, then the material palette's uniform buffer.
inline std::vector<VkDescriptorType> storage_then_palette(int storage) {
  std::vector<VkDescriptorType> types(std::size_t(storage), VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  types.push_back(VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
  return types;
}

/// A pipeline and its layout (one descriptor set, ViewConstants push constants).
class Pipeline {
 public:
  /// A compute pipeline from shader `compute` ("cube_build.comp"); with `workgroup_size`, the
  /// shader's specialisation constant 0 (its workgroup's invocations) set to it.
  Pipeline(VkDevice device, VkDescriptorSetLayout set_layout, const std::string& compute,
           std::uint32_t workgroup_size = 0);
  /// A graphics pipeline (triangle lists, no vertex input, depth test) for `render_pass`.
  Pipeline(VkDevice device, VkDescriptorSetLayout set_layout, VkRenderPass render_pass, const std::string& vertex,
           const std::string& fragment, const GraphicsOptions& options = {});
  /// Destroys its Vulkan objects (after the GPU is done with them).
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  /// The pipeline.
  VkPipeline pipeline() const { return pipeline_; }
  /// Its layout.
  VkPipelineLayout layout() const { return layout_; }
  /// Binds the pipeline and `set` at `bind_point`.
  void bind(VkCommandBuffer commands, VkPipelineBindPoint bind_point, VkDescriptorSet set) const;

 private:
  void create_layout(VkDescriptorSetLayout set_layout);

  VkDevice device_;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace viewer
