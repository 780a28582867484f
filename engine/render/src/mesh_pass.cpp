#include "penumbra/render/mesh_pass.h"

#include <cstring>

#include <glm/gtc/type_ptr.hpp>

namespace penumbra::render {
namespace {
struct Push {
  float model[16];
  float albedo[4];
};
}  // namespace

MeshPass::MeshPass(Device& device, VkFormat color_format, VkFormat depth_format)
    : device_(&device) {
  const VkDescriptorSetLayoutBinding bindings[] = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  layout_ = create_pipeline_layout(device, bindings, sizeof(Push));
  PipelineDesc d;
  d.vertex = Shader::kMeshVert;
  d.fragment = Shader::kMeshFrag;
  d.layout = layout_.get();
  d.color_format = color_format;
  d.depth_format = depth_format;
  d.cull = VK_CULL_MODE_BACK_BIT;
  d.bindings = {{0, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX},
                {1, 3 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX}};
  d.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                  {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 3 * sizeof(float)},
                  {2, 1, VK_FORMAT_R32G32B32_SFLOAT, 0}};
  preview_ = create_pipeline(device, d);
  d.variant = 1;
  lit_ = create_pipeline(device, d);
}

MeshPass::GpuMesh MeshPass::upload(FrameContext& ctx,
                                   const std::shared_ptr<const data::MeshData>& mesh) {
  GpuMesh g;
  g.source = mesh;
  const std::size_t n = mesh->positions.size();
  bool ok = n > 0 && !mesh->indices.empty() && mesh->indices.size() % 3 == 0 &&
            (mesh->normals.empty() || mesh->normals.size() == n);
  for (std::uint32_t i : mesh->indices) ok = ok && i < n;
  if (!ok) {
    ++rejected_;
    return g;
  }
  scratch_.assign(6 * n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) {
    scratch_[6 * i + 0] = mesh->positions[i].x;
    scratch_[6 * i + 1] = mesh->positions[i].y;
    scratch_[6 * i + 2] = mesh->positions[i].z;
    if (!mesh->normals.empty()) {
      scratch_[6 * i + 3] = mesh->normals[i].x;
      scratch_[6 * i + 4] = mesh->normals[i].y;
      scratch_[6 * i + 5] = mesh->normals[i].z;
    }
  }
  const VkDeviceSize vbytes = scratch_.size() * sizeof(float);
  const VkDeviceSize ibytes = mesh->indices.size() * sizeof(std::uint32_t);
  g.vertices =
      create_buffer(ctx.device, vbytes,
                    VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
  g.indices =
      create_buffer(ctx.device, ibytes,
                    VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
  copy_to_buffer(ctx.cmd, ctx.ring, scratch_.data(), vbytes, g.vertices.get());
  copy_to_buffer(ctx.cmd, ctx.ring, mesh->indices.data(), ibytes, g.indices.get());
  g.index_count = static_cast<std::uint32_t>(mesh->indices.size());
  g.vertex_count = static_cast<std::uint32_t>(n);
  g.valid = true;
  return g;
}

void MeshPass::prepare(FrameContext& ctx) {
  draws_.clear();
  bool uploaded = false;
  for (const MeshDraw& d : ctx.packet.meshes) {
    if (!d.mesh) continue;
    auto it = cache_.find(d.mesh.get());
    if (it == cache_.end()) {
      it = cache_.emplace(d.mesh.get(), upload(ctx, d.mesh)).first;
      uploaded = uploaded || it->second.valid;
    }
    GpuMesh& g = it->second;
    g.last_used = ctx.frame;
    if (!g.valid) continue;
    Slice lighting;
    if (d.vertex_lighting && d.vertex_lighting->size() >= g.vertex_count)
      lighting = ctx.ring.upload(d.vertex_lighting->data(), g.vertex_count * sizeof(glm::vec3));
    draws_.push_back({&g, &d, lighting});
  }
  if (uploaded)
    memory_barrier(
        ctx.cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
        VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT | VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT,
        VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT);
  // Evict entries no draw referenced for a while (never ones referenced this frame).
  for (auto it = cache_.begin(); it != cache_.end();) {
    if (it->second.last_used + kEvictAfterFrames < ctx.frame) {
      ctx.retire.retire(ctx.frame, std::move(it->second.vertices));
      ctx.retire.retire(ctx.frame, std::move(it->second.indices));
      it = cache_.erase(it);
    } else {
      ++it;
    }
  }
}

void MeshPass::draw(FrameContext& ctx) {
  triangles_ = 0;
  if (draws_.empty()) return;
  const VkWriteDescriptorSet writes[] = {
      buffer_write(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ctx.camera)};
  int bound = -1;
  for (const Draw& d : draws_) {
    const bool lit = d.lighting.buffer != VK_NULL_HANDLE;
    if (bound != static_cast<int>(lit)) {
      vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                        lit ? lit_.get() : preview_.get());
      if (bound < 0) push_descriptors(*device_, ctx.cmd, layout_.get(), writes);
      bound = static_cast<int>(lit);
    }
    const VkBuffer buffers[] = {d.mesh->vertices.get(),
                                lit ? d.lighting.buffer : d.mesh->vertices.get()};
    const VkDeviceSize offsets[] = {0, lit ? d.lighting.offset : 0};
    vkCmdBindVertexBuffers(ctx.cmd, 0, 2, buffers, offsets);
    vkCmdBindIndexBuffer(ctx.cmd, d.mesh->indices.get(), 0, VK_INDEX_TYPE_UINT32);
    Push push;
    std::memcpy(push.model, glm::value_ptr(d.draw->transform), sizeof push.model);
    push.albedo[0] = d.draw->albedo.x;
    push.albedo[1] = d.draw->albedo.y;
    push.albedo[2] = d.draw->albedo.z;
    push.albedo[3] = 0.0f;
    vkCmdPushConstants(ctx.cmd, layout_.get(),
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                       &push);
    vkCmdDrawIndexed(ctx.cmd, d.mesh->index_count, 1, 0, 0, 0);
    triangles_ += d.mesh->index_count / 3;
  }
}

}  // namespace penumbra::render
