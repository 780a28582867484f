#include "penumbra/render/terrain_pass.h"

#include <cstddef>
#include <cstdint>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "penumbra/render/lighting_texels.h"

namespace penumbra::render {
namespace {
constexpr VkFormat kLightingFormat = VK_FORMAT_R8G8B8A8_UNORM;  // RGBM (lighting_texels.h)

struct TerrainPush {
  float origin_cell[4];
  float albedo[4];         // as shown: 1 in the lighting-only view
  float lighting_size[4];  // xy: texels of the bound lighting texture (1x1 placeholder:
                           // lighting 1), z: RGBM decode scale
  std::int32_t grid[4];    // samples along x, along y; unused
};

bool drawable(const std::shared_ptr<const data::HeightField>& f) {
  return f && f->width >= 2 && f->height >= 2 &&
         f->heights.size() >= static_cast<std::size_t>(f->width) * f->height;
}

bool drawable(const TerrainDraw& t) {
  return t.lighting && t.lighting_width > 0 && t.lighting_height > 0 &&
         t.lighting->size() >= static_cast<std::size_t>(t.lighting_width) * t.lighting_height;
}

Image make_lighting(Device& device, std::uint32_t w, std::uint32_t h) {
  return create_image(device, {{w, h},
                               kLightingFormat,
                               VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                               VK_IMAGE_ASPECT_COLOR_BIT});
}
}  // namespace

TerrainPass::TerrainPass(Device& device, VkFormat color_format, VkFormat depth_format)
    : device_(&device) {
  const VkDescriptorSetLayoutBinding bindings[] = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  layout_ = create_pipeline_layout(device, bindings, sizeof(TerrainPush));
  PipelineDesc d;
  d.vertex = Shader::kTerrainVert;
  d.fragment = Shader::kTerrainFrag;
  d.layout = layout_.get();
  d.color_format = color_format;
  d.depth_format = depth_format;
  d.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  d.cull = VK_CULL_MODE_BACK_BIT;  // slopes facing away are hidden by the terrain in front
  pipeline_ = create_pipeline(device, d);
  sampler_ = create_sampler(device, VK_FILTER_LINEAR, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
  placeholder_ = make_lighting(device, 1, 1);
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    barrier(cmd, {placeholder_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_NONE,
                  VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                  VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL});
    const VkClearColorValue one{{1.0f, 1.0f, 1.0f, 1.0f}};
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, placeholder_.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &one, 1,
                         &range);
    barrier(cmd, {placeholder_.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                  VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  });
}

void TerrainPass::upload_heights(FrameContext& ctx, const data::HeightField& f) {
  const VkDeviceSize bytes = static_cast<VkDeviceSize>(f.width) * f.height * sizeof(float);
  bintree_.build(f);
  if (f.width != grid_w_ || f.height != grid_h_) {
    if (heights_.size) ctx.retire.retire(ctx.frame, std::move(heights_));
    heights_ =
        create_buffer(ctx.device, bytes,
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
    grid_w_ = f.width;
    grid_h_ = f.height;
  } else {
    // In place: the previous frame's vertex reads finish before the copy overwrites them.
    memory_barrier(ctx.cmd, VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_NONE,
                   VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  }
  copy_to_buffer(ctx.cmd, ctx.ring, f.heights.data(), bytes, heights_.get());
  memory_barrier(ctx.cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

void TerrainPass::upload_lighting(FrameContext& ctx, const TerrainDraw& t) {
  const auto w = static_cast<std::uint32_t>(t.lighting_width);
  const auto h = static_cast<std::uint32_t>(t.lighting_height);
  const std::vector<glm::vec3>& rgb = *t.lighting;
  VkImageLayout old_layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  if (!lighting_.image || lighting_.desc.extent.width != w || lighting_.desc.extent.height != h) {
    if (lighting_.image) ctx.retire.retire(ctx.frame, std::move(lighting_));
    lighting_ = make_lighting(ctx.device, w, h);
    old_layout = VK_IMAGE_LAYOUT_UNDEFINED;
  }
  const std::size_t n = static_cast<std::size_t>(w) * h;
  texels_.resize(4 * n);
  lighting_scale_ = pack_rgbm(rgb.data(), n, texels_.data()).scale;
  copy_to_image(ctx.cmd, ctx.ring, texels_.data(), texels_.size(), lighting_, old_layout);
}

void TerrainPass::prepare(FrameContext& ctx) {
  const TerrainDraw& t = ctx.packet.terrain;
  if (!drawable(t.heights)) {
    heights_src_.reset();
  } else if (t.heights != heights_src_) {
    upload_heights(ctx, *t.heights);
    heights_src_ = t.heights;
  }
  if (!drawable(t)) {
    lighting_src_.reset();
  } else if (t.lighting != lighting_src_ || t.lighting_width != lit_w_ ||
             t.lighting_height != lit_h_) {
    upload_lighting(ctx, t);
    lit_w_ = t.lighting_width;
    lit_h_ = t.lighting_height;
    lighting_src_ = t.lighting;
  }
}

void TerrainPass::draw(FrameContext& ctx) {
  triangles_ = 0;
  frame_indices_.clear();
  if (!heights_src_) return;
  const TerrainDraw& t = ctx.packet.terrain;
  const float cell = heights_src_->cell_size;
  // The bintree's frame has sample (0, 0) at the origin.
  TerrainBintree::View view;
  view.view_proj = ctx.view_proj * glm::translate(glm::mat4(1.0f), t.origin);
  view.eye = ctx.packet.camera.position - t.origin;
  view.focal_px = ctx.focal_px;
  view.max_pixels = ctx.packet.view.terrain_lod_pixels;
  triangles_ = bintree_.triangulate(view, frame_indices_);
  if (frame_indices_.empty()) return;

  const Slice indices =
      ctx.ring.upload(frame_indices_.data(), frame_indices_.size() * sizeof(std::uint32_t));
  vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
  const VkDescriptorBufferInfo heights{heights_.get(), 0, VK_WHOLE_SIZE};
  const VkDescriptorImageInfo image{sampler_.get(),
                                    lighting_src_ ? lighting_.view.get() : placeholder_.view.get(),
                                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  const VkWriteDescriptorSet writes[] = {
      buffer_write(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ctx.camera),
      buffer_write(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &heights), image_write(2, &image)};
  push_descriptors(*device_, ctx.cmd, layout_.get(), writes);
  const glm::vec3 albedo = ctx.packet.view.lighting_only ? glm::vec3(1.0f) : t.albedo;
  const float lit_w = lighting_src_ ? static_cast<float>(lit_w_) : 1.0f;
  const float lit_h = lighting_src_ ? static_cast<float>(lit_h_) : 1.0f;
  TerrainPush push{{t.origin.x, t.origin.y, t.origin.z, cell},
                   {albedo.x, albedo.y, albedo.z, 0.0f},
                   {lit_w, lit_h, lighting_src_ ? lighting_scale_ : 1.0f, 0.0f},
                   {grid_w_, grid_h_, 0, 0}};
  vkCmdPushConstants(ctx.cmd, layout_.get(),
                     VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                     &push);
  vkCmdBindIndexBuffer(ctx.cmd, indices.buffer, indices.offset, VK_INDEX_TYPE_UINT32);
  vkCmdDrawIndexed(ctx.cmd, static_cast<std::uint32_t>(frame_indices_.size()), 1, 0, 0, 0);
}

}  // namespace penumbra::render
