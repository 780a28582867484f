// Graphics pipelines for dynamic rendering (no VkRenderPass), and pipeline layouts made of one
// push-descriptor set layout plus one push-constant range: every pass binds its descriptors
// with vkCmdPushDescriptorSetKHR at record time.
//
// Viewport and scissor are dynamic state (a pipeline survives a resize).
//
// Threading: create on any thread that owns the Device's render side; immutable afterwards.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/render/resources.h"
#include "penumbra/render/shaders.h"

namespace penumbra::render {

struct PipelineLayout {
  Unique<VkDescriptorSetLayout> set_layout;
  Unique<VkPipelineLayout> layout;
  VkPipelineLayout get() const { return layout.get(); }
};

// bindings: the push-descriptor set (set 0); push_bytes: 0 for none, visible to vertex and
// fragment stages.
PipelineLayout create_pipeline_layout(Device& device,
                                      std::span<const VkDescriptorSetLayoutBinding> bindings,
                                      std::uint32_t push_bytes);

struct PipelineDesc {
  Shader vertex = Shader::kSkyVert;
  Shader fragment = Shader::kSkyFrag;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::vector<VkVertexInputBindingDescription> bindings;
  std::vector<VkVertexInputAttributeDescription> attributes;
  VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  bool primitive_restart = false;  // strips: index 0xFFFFFFFF starts a new strip
  VkCullModeFlags cull = VK_CULL_MODE_NONE;
  VkFormat color_format = VK_FORMAT_UNDEFINED;  // UNDEFINED: no colour attachment (depth only)
  VkFormat depth_format = VK_FORMAT_UNDEFINED;  // UNDEFINED: no depth attachment
  bool depth_test = true;
  bool depth_write = true;
  VkCompareOp depth_compare = VK_COMPARE_OP_GREATER;  // reversed depth (camera.h)
  // Specialization constant 0 of both stages (`layout(constant_id = 0) const int kVariant`):
  // selects a shader variant at pipeline creation, so a software rasterizer, which runs both
  // sides of a branch under a mask, only compiles the side it needs.
  std::int32_t variant = 0;
};

Unique<VkPipeline> create_pipeline(Device& device, const PipelineDesc& desc);

// Sets viewport and scissor to the whole extent.
void set_viewport(VkCommandBuffer cmd, VkExtent2D extent);

// Binding helpers for vkCmdPushDescriptorSetKHR (loaded once per device).
VkWriteDescriptorSet buffer_write(std::uint32_t binding, VkDescriptorType type,
                                  const VkDescriptorBufferInfo* info);
VkWriteDescriptorSet image_write(std::uint32_t binding, const VkDescriptorImageInfo* info);
void push_descriptors(Device& device, VkCommandBuffer cmd, VkPipelineLayout layout,
                      std::span<const VkWriteDescriptorSet> writes);

}  // namespace penumbra::render
