#include "penumbra/render/mesh_pass.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace penumbra::render {
namespace {
struct MeshPush {
  float model[16];
  float albedo[4];    // rgb: albedo
  float specular[4];  // rgb: Blinn reflectance, a: exponent (environment shading only)
};
}  // namespace

MeshPass::MeshPass(Device& device, VkFormat color_format, VkFormat depth_format)
    : device_(&device) {
  const VkDescriptorSetLayoutBinding bindings[] = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  layout_ = create_pipeline_layout(device, bindings, sizeof(MeshPush));
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

  const VkDescriptorSetLayoutBinding env_bindings[] = {
      {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1,
       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, EnvironmentShading::kMaxSources,
       VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  env_layout_ = create_pipeline_layout(device, env_bindings, sizeof(MeshPush));
  d.vertex = Shader::kMeshEnvVert;
  d.fragment = Shader::kMeshEnvFrag;
  d.layout = env_layout_.get();
  d.bindings = {{0, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX}};
  d.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                  {1, 0, VK_FORMAT_R32G32B32_SFLOAT, 3 * sizeof(float)}};
  env_desc_ = d;
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
  g.lo = g.hi = mesh->positions[0];
  for (const glm::vec3& p : mesh->positions) {
    g.lo = glm::min(g.lo, p);
    g.hi = glm::max(g.hi, p);
  }
  g.valid = true;
  return g;
}

void MeshPass::prepare(FrameContext& ctx) {
  draws_.clear();
  have_bounds_ = false;
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
    for (int c = 0; c < 8; ++c) {
      const glm::vec3 corner((c & 1) ? g.hi.x : g.lo.x, (c & 2) ? g.hi.y : g.lo.y,
                             (c & 4) ? g.hi.z : g.lo.z);
      const glm::vec3 w(d.transform * glm::vec4(corner, 1.0f));
      lo_ = have_bounds_ ? glm::min(lo_, w) : w;
      hi_ = have_bounds_ ? glm::max(hi_, w) : w;
      have_bounds_ = true;
    }
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

bool MeshPass::bounds(glm::vec3& lo, glm::vec3& hi) const {
  if (!have_bounds_) return false;
  lo = lo_;
  hi = hi_;
  return true;
}

void MeshPass::append_geometry_key(std::vector<std::uint64_t>& key) const {
  for (const Draw& d : draws_) {
    key.push_back(reinterpret_cast<std::uintptr_t>(d.mesh->source.get()));
    const float* m = glm::value_ptr(d.draw->transform);
    for (int i = 0; i < 16; ++i) key.push_back(std::bit_cast<std::uint32_t>(m[i]));
  }
}

void MeshPass::draw_depth(VkCommandBuffer cmd, VkPipelineLayout layout,
                          const glm::mat4& view_proj) const {
  for (const Draw& d : draws_) {
    const VkBuffer buffer = d.mesh->vertices.get();
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &buffer, &offset);
    vkCmdBindIndexBuffer(cmd, d.mesh->indices.get(), 0, VK_INDEX_TYPE_UINT32);
    const glm::mat4 mvp = view_proj * d.draw->transform;
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                       sizeof mvp, glm::value_ptr(mvp));
    vkCmdDrawIndexed(cmd, d.mesh->index_count, 1, 0, 0, 0);
  }
}

void MeshPass::draw(FrameContext& ctx) {
  triangles_ = 0;
  if (draws_.empty()) return;
  if (ctx.environment != nullptr) {
    draw_environment(ctx);
    return;
  }
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
    MeshPush push;
    std::memcpy(push.model, glm::value_ptr(d.draw->transform), sizeof push.model);
    push.albedo[0] = d.draw->albedo.x;
    push.albedo[1] = d.draw->albedo.y;
    push.albedo[2] = d.draw->albedo.z;
    push.albedo[3] = 0.0f;
    std::memset(push.specular, 0, sizeof push.specular);
    vkCmdPushConstants(ctx.cmd, layout_.get(),
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                       &push);
    vkCmdDrawIndexed(ctx.cmd, d.mesh->index_count, 1, 0, 0, 0);
    triangles_ += d.mesh->index_count / 3;
  }
}

void MeshPass::draw_environment(FrameContext& ctx) {
  const EnvironmentBindings& e = *ctx.environment;
  const VkWriteDescriptorSet maps = [&] {
    VkWriteDescriptorSet w = image_write(2, e.maps);
    w.descriptorCount = EnvironmentShading::kMaxSources;
    return w;
  }();
  const VkWriteDescriptorSet writes[] = {
      buffer_write(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ctx.camera),
      buffer_write(1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &e.block), maps};
  const int variant = static_cast<int>(std::min<std::size_t>(ctx.packet.environment.sources.size(),
                                                             EnvironmentShading::kMaxSources)) +
                      (ctx.packet.environment.direct_diffuse ? 4 : 0);
  if (!env_[variant]) {
    env_desc_.variant = variant;
    env_[variant] = create_pipeline(*device_, env_desc_);
  }
  vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, env_[variant].get());
  push_descriptors(*device_, ctx.cmd, env_layout_.get(), writes);
  for (const Draw& d : draws_) {
    const VkBuffer buffer = d.mesh->vertices.get();
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(ctx.cmd, 0, 1, &buffer, &offset);
    vkCmdBindIndexBuffer(ctx.cmd, d.mesh->indices.get(), 0, VK_INDEX_TYPE_UINT32);
    MeshPush push;
    std::memcpy(push.model, glm::value_ptr(d.draw->transform), sizeof push.model);
    const glm::vec3& a = d.draw->albedo;
    const glm::vec3& s = d.draw->specular;
    const float exponent = std::max(0.0f, d.draw->specular_exponent);
    const float on = exponent > 0.0f ? 1.0f : 0.0f;
    const float albedo[4] = {a.x, a.y, a.z, 0.0f};
    const float specular[4] = {on * s.x, on * s.y, on * s.z, exponent};
    std::memcpy(push.albedo, albedo, sizeof albedo);
    std::memcpy(push.specular, specular, sizeof specular);
    vkCmdPushConstants(ctx.cmd, env_layout_.get(),
                       VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                       &push);
    vkCmdDrawIndexed(ctx.cmd, d.mesh->index_count, 1, 0, 0, 0);
    triangles_ += d.mesh->index_count / 3;
  }
}

}  // namespace penumbra::render
