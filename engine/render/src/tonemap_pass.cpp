#include "penumbra/render/tonemap_pass.h"

#include <cmath>

namespace penumbra::render {

TonemapPass::TonemapPass(Device& device, VkFormat ldr_format) : device_(&device) {
  const VkDescriptorSetLayoutBinding bindings[] = {
      {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  layout_ = create_pipeline_layout(device, bindings, 4 * sizeof(float));
  PipelineDesc d;
  d.vertex = Shader::kTonemapVert;
  d.fragment = Shader::kTonemapFrag;
  d.layout = layout_.get();
  d.color_format = ldr_format;
  pipeline_ = create_pipeline(device, d);
  sampler_ = create_sampler(device, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
}

void TonemapPass::draw(VkCommandBuffer cmd, const Image& hdr, const ViewSettings& view) {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
  const VkDescriptorImageInfo image{sampler_.get(), hdr.view.get(),
                                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  const VkWriteDescriptorSet writes[] = {image_write(0, &image)};
  push_descriptors(*device_, cmd, layout_.get(), writes);
  const float params[4] = {std::exp2(view.exposure_ev),
                           view.tonemap == ViewSettings::Tonemap::kLinear ? 1.0f : 0.0f, 0, 0};
  vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                     0, sizeof params, params);
  vkCmdDraw(cmd, 3, 1, 0, 0);
}

}  // namespace penumbra::render
