#include "penumbra/render/sky_pass.h"

#include <cstdint>
#include <cstring>
#include <vector>

#include <glm/gtc/packing.hpp>

namespace penumbra::render {
namespace {
constexpr VkFormat kEnvFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

// Blocking upload through a temporary staging buffer, leaving the image shader-readable.
void upload_blocking(Device& device, const Image& image, const std::vector<std::uint16_t>& texels,
                     VkImageLayout old_layout) {
  const VkDeviceSize bytes = texels.size() * sizeof(std::uint16_t);
  Buffer staging = create_buffer(device, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
  std::memcpy(staging.mapped, texels.data(), bytes);
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    barrier(cmd, {image.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                  VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                  old_layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL});
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {image.desc.extent.width, image.desc.extent.height, 1};
    vkCmdCopyBufferToImage(cmd, staging.get(), image.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &region);
    barrier(cmd, {image.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                  VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  });
}

Image make_texture(Device& device, std::uint32_t w, std::uint32_t h) {
  return create_image(device, {{w, h},
                               kEnvFormat,
                               VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                               VK_IMAGE_ASPECT_COLOR_BIT});
}
}  // namespace

SkyPass::SkyPass(Device& device, VkFormat color_format, VkFormat depth_format) : device_(&device) {
  const VkDescriptorSetLayoutBinding bindings[] = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  layout_ = create_pipeline_layout(device, bindings, 0);
  PipelineDesc d;
  d.vertex = Shader::kSkyVert;
  d.fragment = Shader::kSkyFrag;
  d.layout = layout_.get();
  d.color_format = color_format;
  d.depth_format = depth_format;
  d.depth_write = false;
  d.depth_compare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // only where the clear value (0) remains
  procedural_ = create_pipeline(device, d);
  d.variant = 1;
  environment_pipeline_ = create_pipeline(device, d);
  sampler_ = create_sampler(device, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  placeholder_ = make_texture(device, 1, 1);
  upload_blocking(device, placeholder_, std::vector<std::uint16_t>(4, 0),
                  VK_IMAGE_LAYOUT_UNDEFINED);
}

void SkyPass::prepare(FrameContext& ctx) {
  const auto& env = ctx.packet.sky.environment;
  const bool valid = env && env->width > 0 && env->height > 0 &&
                     env->rgb.size() >= static_cast<std::size_t>(env->width) * env->height * 3;
  if (!valid) {
    if (uploaded_) {
      ctx.retire.retire(ctx.frame, std::move(environment_));
      uploaded_.reset();
    }
    return;
  }
  if (env == uploaded_) return;
  const auto w = static_cast<std::uint32_t>(env->width),
             h = static_cast<std::uint32_t>(env->height);
  std::vector<std::uint16_t> texels(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < static_cast<std::size_t>(w) * h; ++i) {
    for (int c = 0; c < 3; ++c) texels[4 * i + c] = glm::packHalf1x16(env->rgb[3 * i + c]);
    texels[4 * i + 3] = glm::packHalf1x16(1.0f);
  }
  if (uploaded_) ctx.retire.retire(ctx.frame, std::move(environment_));
  environment_ = make_texture(*device_, w, h);
  upload_blocking(*device_, environment_, texels, VK_IMAGE_LAYOUT_UNDEFINED);
  uploaded_ = env;
}

void SkyPass::draw(FrameContext& ctx) {
  vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                    uploaded_ ? environment_pipeline_.get() : procedural_.get());
  const VkDescriptorImageInfo image{sampler_.get(),
                                    uploaded_ ? environment_.view.get() : placeholder_.view.get(),
                                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  const VkWriteDescriptorSet writes[] = {
      buffer_write(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ctx.camera), image_write(1, &image)};
  push_descriptors(*device_, ctx.cmd, layout_.get(), writes);
  vkCmdDraw(ctx.cmd, 3, 1, 0, 0);
}

}  // namespace penumbra::render
