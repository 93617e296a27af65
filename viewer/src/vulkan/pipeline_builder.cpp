#include "vulkan/pipeline_builder.hpp"

#include <cstdint>

#include "vulkan/shader_loader.hpp"
#include "renderers/view_constants.hpp"
#include "vulkan/vulkan_check.hpp"

namespace viewer {

DescriptorSets::DescriptorSets(VkDevice device, const std::vector<VkDescriptorType>& types) : device_(device), types_(types) {
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  std::vector<VkDescriptorPoolSize> sizes;
  for (std::size_t i = 0; i < types.size(); ++i) {
    bindings.push_back({std::uint32_t(i), types[i], 1, VK_SHADER_STAGE_ALL, nullptr});
    sizes.push_back({types[i], std::uint32_t(kFramesInFlight)});
  }
  VkDescriptorSetLayoutCreateInfo layout{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  layout.bindingCount = std::uint32_t(bindings.size());
  layout.pBindings = bindings.data();
  vk_check(vkCreateDescriptorSetLayout(device_, &layout, nullptr, &layout_), "vkCreateDescriptorSetLayout");
  VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool.maxSets = kFramesInFlight;
  pool.poolSizeCount = std::uint32_t(sizes.size());
  pool.pPoolSizes = sizes.data();
  vk_check(vkCreateDescriptorPool(device_, &pool, nullptr, &pool_), "vkCreateDescriptorPool");
  std::array<VkDescriptorSetLayout, kFramesInFlight> layouts;
  layouts.fill(layout_);
  VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocate.descriptorPool = pool_;
  allocate.descriptorSetCount = kFramesInFlight;
  allocate.pSetLayouts = layouts.data();
  vk_check(vkAllocateDescriptorSets(device_, &allocate, sets_.data()), "vkAllocateDescriptorSets");
}

DescriptorSets::~DescriptorSets() {
  vkDestroyDescriptorPool(device_, pool_, nullptr);
  vkDestroyDescriptorSetLayout(device_, layout_, nullptr);
}

void DescriptorSets::write_buffer(int binding, VkBuffer buffer) {
  for (int slot = 0; slot < kFramesInFlight; ++slot) write_buffer(slot, binding, buffer);
}

void DescriptorSets::write_buffer(int slot, int binding, VkBuffer buffer) {
  VkDescriptorBufferInfo info{buffer, 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = sets_[slot];
  write.dstBinding = std::uint32_t(binding);
  write.descriptorCount = 1;
  write.descriptorType = types_.at(std::size_t(binding));
  write.pBufferInfo = &info;
  vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
}

void DescriptorSets::write_storage_image(int binding, VkImageView view) {
  for (int slot = 0; slot < kFramesInFlight; ++slot) {
    VkDescriptorImageInfo info{VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = sets_[slot];
    write.dstBinding = std::uint32_t(binding);
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    write.pImageInfo = &info;
    vkUpdateDescriptorSets(device_, 1, &write, 0, nullptr);
  }
}

void Pipeline::create_layout(VkDescriptorSetLayout set_layout) {
  VkPushConstantRange range{VK_SHADER_STAGE_ALL, 0, sizeof(ViewConstants)};
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = 1;
  info.pSetLayouts = &set_layout;
  info.pushConstantRangeCount = 1;
  info.pPushConstantRanges = &range;
  vk_check(vkCreatePipelineLayout(device_, &info, nullptr, &layout_), "vkCreatePipelineLayout");
}

Pipeline::Pipeline(VkDevice device, VkDescriptorSetLayout set_layout, const std::string& compute,
                   std::uint32_t workgroup_size)
    : device_(device) {
  create_layout(set_layout);
  VkShaderModule module = load_shader(device_, compute);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  const VkSpecializationMapEntry entry{0, 0, sizeof(std::uint32_t)};
  const VkSpecializationInfo specialization{1, &entry, sizeof(std::uint32_t), &workgroup_size};
  if (workgroup_size != 0) info.stage.pSpecializationInfo = &specialization;
  info.layout = layout_;
  const VkResult result = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  vkDestroyShaderModule(device_, module, nullptr);
  vk_check(result, ("vkCreateComputePipelines " + compute).c_str());
}

Pipeline::Pipeline(VkDevice device, VkDescriptorSetLayout set_layout, VkRenderPass render_pass,
                   const std::string& vertex, const std::string& fragment, const GraphicsOptions& options)
    : device_(device) {
  create_layout(set_layout);
  VkShaderModule vertex_module = load_shader(device_, vertex);
  VkShaderModule fragment_module = VK_NULL_HANDLE;
  try {
    fragment_module = load_shader(device_, fragment);
  } catch (...) {
    vkDestroyShaderModule(device_, vertex_module, nullptr);
    throw;
  }
  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vertex_module;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = fragment_module;
  stages[1].pName = "main";
  VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = options.cull;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = VK_TRUE;
  depth.depthWriteEnable = options.depth_write ? VK_TRUE : VK_FALSE;
  depth.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
  VkPipelineColorBlendAttachmentState blend_attachment{};
  blend_attachment.colorWriteMask =
      VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  if (options.blend) {
    blend_attachment.blendEnable = VK_TRUE;
    blend_attachment.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
    blend_attachment.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    blend_attachment.colorBlendOp = VK_BLEND_OP_ADD;
    blend_attachment.srcAlphaBlendFactor = VK_BLEND_FACTOR_ZERO;
    blend_attachment.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    blend_attachment.alphaBlendOp = VK_BLEND_OP_ADD;
  }
  VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend.attachmentCount = 1;
  blend.pAttachments = &blend_attachment;
  const VkDynamicState dynamic_states[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;
  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.stageCount = 2;
  info.pStages = stages;
  info.pVertexInputState = &vertex_input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = layout_;
  info.renderPass = render_pass;
  const VkResult result = vkCreateGraphicsPipelines(device_, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  vkDestroyShaderModule(device_, vertex_module, nullptr);
  vkDestroyShaderModule(device_, fragment_module, nullptr);
  vk_check(result, ("vkCreateGraphicsPipelines " + vertex + " + " + fragment).c_str());
}

Pipeline::~Pipeline() {
  if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
}

void Pipeline::bind(VkCommandBuffer commands, VkPipelineBindPoint bind_point, VkDescriptorSet set) const {
  vkCmdBindPipeline(commands, bind_point, pipeline_);
  vkCmdBindDescriptorSets(commands, bind_point, layout_, 0, 1, &set, 0, nullptr);
}

}  // namespace viewer
