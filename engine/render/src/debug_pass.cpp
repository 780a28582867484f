#include "penumbra/render/debug_pass.h"

#include <cmath>
#include <cstddef>
#include <cstring>

namespace penumbra::render {
namespace {
static_assert(sizeof(PointDraw) == 6 * sizeof(float), "PointDraw is uploaded as is");
static_assert(sizeof(SphereDraw) == 7 * sizeof(float), "SphereDraw is uploaded as is");
}  // namespace

DebugPass::DebugPass(Device& device, VkFormat color_format, VkFormat depth_format)
    : device_(&device) {
  const VkDescriptorSetLayoutBinding bindings[] = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr}};
  layout_ = create_pipeline_layout(device, bindings, 0);
  PipelineDesc d;
  d.vertex = Shader::kDebugVert;
  d.fragment = Shader::kDebugFrag;
  d.layout = layout_.get();
  d.color_format = color_format;
  d.depth_format = depth_format;
  d.bindings = {{0, sizeof(PointDraw), VK_VERTEX_INPUT_RATE_VERTEX}};
  d.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                  {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(PointDraw, color)}};
  d.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
  lines_ = create_pipeline(device, d);
  d.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
  points_ = create_pipeline(device, d);

  d.vertex = Shader::kDebugSphereVert;
  d.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
  d.bindings = {{0, 3 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX},
                {1, sizeof(SphereDraw), VK_VERTEX_INPUT_RATE_INSTANCE}};
  d.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                  {1, 1, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SphereDraw, center)},
                  {2, 1, VK_FORMAT_R32_SFLOAT, offsetof(SphereDraw, radius)},
                  {3, 1, VK_FORMAT_R32G32B32_SFLOAT, offsetof(SphereDraw, color)}};
  spheres_ = create_pipeline(device, d);

  // Unit wire sphere: great circles in the xy, yz and zx planes, as a line list.
  std::vector<float> v;
  const float step = 2.0f * 3.14159265358979f / kSegments;
  for (int plane = 0; plane < 3; ++plane) {
    for (std::uint32_t s = 0; s < kSegments; ++s) {
      for (std::uint32_t k : {s, s + 1}) {
        const float a = std::cos(k * step), b = std::sin(k * step);
        float p[3] = {0, 0, 0};
        p[plane] = a;
        p[(plane + 1) % 3] = b;
        v.insert(v.end(), p, p + 3);
      }
    }
  }
  unit_vertices_ = static_cast<std::uint32_t>(v.size() / 3);
  const VkDeviceSize bytes = v.size() * sizeof(float);
  unit_sphere_ = create_buffer(
      device, bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
  Buffer staging = create_buffer(device, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
  std::memcpy(staging.mapped, v.data(), bytes);
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(cmd, staging.get(), unit_sphere_.get(), 1, &region);
  });
}

void DebugPass::prepare(FrameContext& ctx) {
  const RenderPacket& p = ctx.packet;
  point_count_ = static_cast<std::uint32_t>(p.points.size());
  sphere_count_ = static_cast<std::uint32_t>(p.spheres.size());
  line_vertices_ = static_cast<std::uint32_t>(2 * p.lines.size());
  if (point_count_ > 0)
    point_data_ = ctx.ring.upload(p.points.data(), p.points.size() * sizeof(PointDraw));
  if (sphere_count_ > 0)
    sphere_data_ = ctx.ring.upload(p.spheres.data(), p.spheres.size() * sizeof(SphereDraw));
  if (line_vertices_ > 0) {
    scratch_.clear();
    for (const LineDraw& l : p.lines) {
      scratch_.push_back({l.a, l.color});
      scratch_.push_back({l.b, l.color});
    }
    line_data_ = ctx.ring.upload(scratch_.data(), scratch_.size() * sizeof(PointDraw));
  }
}

void DebugPass::draw(FrameContext& ctx) {
  if (point_count_ + sphere_count_ + line_vertices_ == 0) return;
  const VkWriteDescriptorSet writes[] = {
      buffer_write(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ctx.camera)};
  if (sphere_count_ > 0) {
    vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, spheres_.get());
    push_descriptors(*device_, ctx.cmd, layout_.get(), writes);
    const VkBuffer buffers[] = {unit_sphere_.get(), sphere_data_.buffer};
    const VkDeviceSize offsets[] = {0, sphere_data_.offset};
    vkCmdBindVertexBuffers(ctx.cmd, 0, 2, buffers, offsets);
    vkCmdDraw(ctx.cmd, unit_vertices_, sphere_count_, 0, 0);
  }
  if (line_vertices_ > 0) {
    vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, lines_.get());
    push_descriptors(*device_, ctx.cmd, layout_.get(), writes);
    vkCmdBindVertexBuffers(ctx.cmd, 0, 1, &line_data_.buffer, &line_data_.offset);
    vkCmdDraw(ctx.cmd, line_vertices_, 1, 0, 0);
  }
  if (point_count_ > 0) {
    vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, points_.get());
    push_descriptors(*device_, ctx.cmd, layout_.get(), writes);
    vkCmdBindVertexBuffers(ctx.cmd, 0, 1, &point_data_.buffer, &point_data_.offset);
    vkCmdDraw(ctx.cmd, point_count_, 1, 0, 0);
  }
}

}  // namespace penumbra::render
