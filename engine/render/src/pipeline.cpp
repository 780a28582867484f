#include "penumbra/render/pipeline.h"

#include "penumbra/render/vk_check.h"

namespace penumbra::render {

PipelineLayout create_pipeline_layout(Device& device,
                                      std::span<const VkDescriptorSetLayoutBinding> bindings,
                                      std::uint32_t push_bytes) {
  PipelineLayout out;
  VkDescriptorSetLayoutCreateInfo set = vk_struct<VkDescriptorSetLayoutCreateInfo>(
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
  set.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  set.bindingCount = static_cast<std::uint32_t>(bindings.size());
  set.pBindings = bindings.data();
  VkDescriptorSetLayout sl = VK_NULL_HANDLE;
  vk_check(vkCreateDescriptorSetLayout(device.handle(), &set, nullptr, &sl),
           "vkCreateDescriptorSetLayout");
  out.set_layout = Unique<VkDescriptorSetLayout>(device, sl, vkDestroyDescriptorSetLayout,
                                                 ObjectKind::kSetLayout);
  VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                            push_bytes};
  VkPipelineLayoutCreateInfo info =
      vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
  info.setLayoutCount = 1;
  info.pSetLayouts = &sl;
  info.pushConstantRangeCount = push_bytes > 0 ? 1 : 0;
  info.pPushConstantRanges = &range;
  VkPipelineLayout pl = VK_NULL_HANDLE;
  vk_check(vkCreatePipelineLayout(device.handle(), &info, nullptr, &pl), "vkCreatePipelineLayout");
  out.layout =
      Unique<VkPipelineLayout>(device, pl, vkDestroyPipelineLayout, ObjectKind::kPipelineLayout);
  return out;
}

Unique<VkPipeline> create_pipeline(Device& device, const PipelineDesc& d) {
  Unique<VkShaderModule> vs = create_shader_module(device, d.vertex);
  Unique<VkShaderModule> fs = create_shader_module(device, d.fragment);
  VkPipelineShaderStageCreateInfo stages[2] = {
      vk_struct<VkPipelineShaderStageCreateInfo>(
          VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO),
      vk_struct<VkPipelineShaderStageCreateInfo>(
          VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO)};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vs.get();
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = fs.get();
  stages[1].pName = "main";
  const VkSpecializationMapEntry entry{0, 0, sizeof(std::int32_t)};
  const VkSpecializationInfo specialization{1, &entry, sizeof d.variant, &d.variant};
  stages[0].pSpecializationInfo = &specialization;
  stages[1].pSpecializationInfo = &specialization;

  VkPipelineVertexInputStateCreateInfo input = vk_struct<VkPipelineVertexInputStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO);
  input.vertexBindingDescriptionCount = static_cast<std::uint32_t>(d.bindings.size());
  input.pVertexBindingDescriptions = d.bindings.data();
  input.vertexAttributeDescriptionCount = static_cast<std::uint32_t>(d.attributes.size());
  input.pVertexAttributeDescriptions = d.attributes.data();
  VkPipelineInputAssemblyStateCreateInfo assembly =
      vk_struct<VkPipelineInputAssemblyStateCreateInfo>(
          VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO);
  assembly.topology = d.topology;
  assembly.primitiveRestartEnable = d.primitive_restart ? VK_TRUE : VK_FALSE;
  VkPipelineViewportStateCreateInfo viewport = vk_struct<VkPipelineViewportStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO);
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster = vk_struct<VkPipelineRasterizationStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO);
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = d.cull;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample =
      vk_struct<VkPipelineMultisampleStateCreateInfo>(
          VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO);
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth = vk_struct<VkPipelineDepthStencilStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO);
  const bool has_depth = d.depth_format != VK_FORMAT_UNDEFINED;
  depth.depthTestEnable = has_depth && d.depth_test;
  depth.depthWriteEnable = has_depth && d.depth_write;
  depth.depthCompareOp = d.depth_compare;
  VkPipelineColorBlendAttachmentState attachment{};
  attachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                              VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo blend = vk_struct<VkPipelineColorBlendStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO);
  const bool has_color = d.color_format != VK_FORMAT_UNDEFINED;  // depth-only (shadow maps)
  blend.attachmentCount = has_color ? 1 : 0;
  blend.pAttachments = &attachment;
  const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic = vk_struct<VkPipelineDynamicStateCreateInfo>(
      VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO);
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;
  VkPipelineRenderingCreateInfo rendering =
      vk_struct<VkPipelineRenderingCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO);
  rendering.colorAttachmentCount = has_color ? 1 : 0;
  rendering.pColorAttachmentFormats = &d.color_format;
  rendering.depthAttachmentFormat = d.depth_format;

  VkGraphicsPipelineCreateInfo info =
      vk_struct<VkGraphicsPipelineCreateInfo>(VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO);
  info.pNext = &rendering;
  info.stageCount = 2;
  info.pStages = stages;
  info.pVertexInputState = &input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = d.layout;
  VkPipeline p = VK_NULL_HANDLE;
  vk_check(vkCreateGraphicsPipelines(device.handle(), VK_NULL_HANDLE, 1, &info, nullptr, &p),
           (std::string("vkCreateGraphicsPipelines ") + shader_name(d.vertex)).c_str());
  return Unique<VkPipeline>(device, p, vkDestroyPipeline, ObjectKind::kPipeline);
}

void set_viewport(VkCommandBuffer cmd, VkExtent2D extent) {
  const VkViewport vp{
      0.0f, 0.0f, static_cast<float>(extent.width), static_cast<float>(extent.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(cmd, 0, 1, &vp);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

VkWriteDescriptorSet buffer_write(std::uint32_t binding, VkDescriptorType type,
                                  const VkDescriptorBufferInfo* info) {
  VkWriteDescriptorSet w = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pBufferInfo = info;
  return w;
}

VkWriteDescriptorSet image_write(std::uint32_t binding, const VkDescriptorImageInfo* info) {
  VkWriteDescriptorSet w = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  w.pImageInfo = info;
  return w;
}

void push_descriptors(Device& device, VkCommandBuffer cmd, VkPipelineLayout layout,
                      std::span<const VkWriteDescriptorSet> writes) {
  device.push_descriptor_fn()(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0,
                              static_cast<std::uint32_t>(writes.size()), writes.data());
}

}  // namespace penumbra::render
