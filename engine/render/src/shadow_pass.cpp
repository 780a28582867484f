#include "penumbra/render/shadow_pass.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "penumbra/data/finite.h"
#include "penumbra/render/mesh_pass.h"
#include "penumbra/render/vk_check.h"

namespace penumbra::render {
namespace {
constexpr VkFormat kShadowFormat = VK_FORMAT_D32_SFLOAT;
constexpr std::size_t kMaxSets = std::size_t{1} << EnvironmentShading::kMaxSources;

// Mirrors EnvironmentBlock in shaders/mesh.glsl (std140).
struct EnvironmentBlock {
  glm::mat4 shadow_view_proj[EnvironmentShading::kMaxSources];
  glm::vec4 source_direction[EnvironmentShading::kMaxSources];
  glm::vec4 source_irradiance[EnvironmentShading::kMaxSources];
  glm::vec4 params;
  glm::vec4 sets[kMaxSets * 9];
};
static_assert(sizeof(EnvironmentBlock) == 3 * 64 + 6 * 16 + 16 + 72 * 16);

using data::finite;
}  // namespace

std::string check_environment_shading(const EnvironmentShading& s) {
  if (!s.enabled || s.sources.empty()) return {};
  const std::uint32_t n = s.oem_source_count;
  if (n < 1 || n > 8)
    return "environment.oem_source_count: " + std::to_string(n) + ", expected 1..8 with sources";
  const std::size_t expected = (std::size_t{1} << n) * 27;
  if (!s.oem_sh) return "environment.oem_sh: null with " + std::to_string(n) + " sources";
  if (s.oem_sh->size() != expected)
    return "environment.oem_sh: " + std::to_string(s.oem_sh->size()) + " floats, expected " +
           std::to_string(expected) + " (2^" + std::to_string(n) + " sets x 27)";
  for (std::size_t i = 0; i < s.oem_sh->size(); ++i)
    if (!std::isfinite((*s.oem_sh)[i]))
      return "environment.oem_sh: value " + std::to_string(i) + " is not finite";
  if (s.present_mask >> n)
    return "environment.present_mask: bits past oem_source_count " + std::to_string(n);
  std::uint32_t used = s.present_mask;
  const std::size_t k_max = std::min(s.sources.size(), EnvironmentShading::kMaxSources);
  for (std::size_t k = 0; k < k_max; ++k) {
    const ShadowedSource& src = s.sources[k];
    const std::string name = "environment.sources[" + std::to_string(k) + "]";
    if (src.oem_bit >= n)
      return name + ".oem_bit: " + std::to_string(src.oem_bit) + ", expected < " +
             std::to_string(n);
    if (used & (1u << src.oem_bit))
      return name + ".oem_bit: " + std::to_string(src.oem_bit) +
             " is another source's or in present_mask";
    used |= 1u << src.oem_bit;
    if (!finite(src.direction) || glm::length(src.direction) < 1e-6f)
      return name + ".direction: zero or not finite";
    if (!finite(src.irradiance) ||
        glm::min(src.irradiance.x, glm::min(src.irradiance.y, src.irradiance.z)) < 0)
      return name + ".irradiance: negative or not finite";
    if (!(src.weight >= 0.0f && src.weight <= 1.0f))
      return name + ".weight: " + std::to_string(src.weight) + ", expected in [0, 1]";
  }
  return {};
}

ShadowBox fit_shadow_box(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& direction) {
  ShadowBox box;
  const float len = glm::length(direction);
  if (!(len > 0.0f) || !std::isfinite(len) || !finite(lo) || !finite(hi)) return box;
  const glm::vec3 d = direction / len;
  const glm::vec3 f = -d;  // the light looks along -d, from the source into the scene
  // A helper axis far from f: z unless the source is near the zenith or nadir.
  const glm::vec3 helper = std::abs(d.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
  const glm::vec3 r = glm::normalize(glm::cross(f, helper));
  // r x u = f: the same handedness as the camera's framebuffer (x right, y down, z away), so
  // the pipeline's counter-clockwise front faces are the camera pass's.
  const glm::vec3 u = glm::cross(f, r);
  glm::vec3 mn(INFINITY), mx(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    const glm::vec3 q(glm::dot(r, p), glm::dot(u, p), glm::dot(f, p));
    mn = glm::min(mn, q);
    mx = glm::max(mx, q);
  }
  for (int i = 0; i < 3; ++i) {
    const float pad = std::max(0.01f * (mx[i] - mn[i]), 0.001f);
    mn[i] -= pad;
    mx[i] += pad;
  }
  const glm::vec3 size = mx - mn;
  box.extent = size;
  const float sx = 2.0f / size.x, sy = 2.0f / size.y, sz = 1.0f / size.z;
  glm::mat4 m(0.0f);
  const glm::vec3 axes[3] = {r * sx, u * sy, f * sz};
  const float offsets[3] = {-(mn.x + mx.x) / size.x, -(mn.y + mx.y) / size.y, -mn.z * sz};
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) m[col][row] = axes[row][col];
    m[3][row] = offsets[row];
  }
  m[3][3] = 1.0f;
  box.view_proj = m;
  return box;
}

std::vector<glm::vec3> environment_sets(const EnvironmentShading& s) {
  const std::size_t k_count = std::min(s.sources.size(), EnvironmentShading::kMaxSources);
  const std::size_t sets = std::size_t{1} << k_count;
  const std::vector<float>& oem = *s.oem_sh;
  // [Ramamoorthi01] eq. 8: A_l = pi, 2 pi / 3, pi / 4; divided by pi (radiance per unit albedo).
  constexpr float kBand[9] = {1.0f,  2.0f / 3.0f, 2.0f / 3.0f, 2.0f / 3.0f, 0.25f,
                              0.25f, 0.25f,       0.25f,       0.25f};
  auto add_set = [&](std::size_t env_index, float weight, glm::vec3* out) {
    const float* c = oem.data() + env_index * 27;  // 3 channels x 9
    for (int i = 0; i < 9; ++i) out[i] += weight * kBand[i] * glm::vec3(c[i], c[9 + i], c[18 + i]);
  };
  std::vector<glm::vec3> out(sets * 9, glm::vec3(0.0f));
  for (std::size_t v = 0; v < sets; ++v) {
    glm::vec3* set = out.data() + v * 9;
    if (s.direct_diffuse) {
      add_set(s.present_mask, 1.0f, set);
      continue;
    }
    // Every subset U of V, weighted prod_{k in U} w_k prod_{k in V \ U} (1 - w_k).
    for (std::size_t u = v;; u = (u - 1) & v) {
      float weight = 1.0f;
      std::size_t index = s.present_mask;
      for (std::size_t k = 0; k < k_count; ++k) {
        if (!(v >> k & 1)) continue;
        const float w = s.sources[k].weight;
        if (u >> k & 1) {
          weight *= w;
          index |= std::size_t{1} << s.sources[k].oem_bit;
        } else {
          weight *= 1.0f - w;
        }
      }
      if (weight > 0.0f) add_set(index, weight, set);
      if (u == 0) break;
    }
  }
  return out;
}

ShadowPass::ShadowPass(Device& device) : device_(&device) {
  layout_ = create_pipeline_layout(device, {}, sizeof(glm::mat4));
  PipelineDesc d;
  d.vertex = Shader::kShadowVert;
  d.fragment = Shader::kShadowFrag;
  d.layout = layout_.get();
  d.depth_format = kShadowFormat;
  d.depth_compare = VK_COMPARE_OP_LESS;  // plain depth: 0 nearest the source
  d.cull = VK_CULL_MODE_FRONT_BIT;       // [Ambrosj16] sec. 3.6
  d.bindings = {{0, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX}};
  d.attributes = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
  pipeline_ = create_pipeline(device, d);
  sampler_ = create_sampler(device, VK_FILTER_NEAREST, VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE);
}

void ShadowPass::prepare(FrameContext& ctx, const MeshPass& meshes) {
  const EnvironmentShading& s = ctx.packet.environment;
  active_ = false;
  error_ = check_environment_shading(s);
  glm::vec3 lo, hi;
  if (!s.enabled || s.sources.empty() || !error_.empty() || !meshes.bounds(lo, hi)) return;
  count_ = std::min(s.sources.size(), EnvironmentShading::kMaxSources);
  const std::uint32_t size = std::clamp<std::uint32_t>(s.shadow_map_size, 64, 4096);
  if (images_.size() != count_ || size != size_) {
    key_.clear();  // new images: render them
    for (Image& image : images_) ctx.retire.retire(ctx.frame, std::move(image));
    images_.clear();
    for (std::size_t k = 0; k < count_; ++k)
      images_.push_back(create_image(
          *device_, {{size, size},
                     kShadowFormat,
                     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                     VK_IMAGE_ASPECT_DEPTH_BIT}));
    size_ = size;
  }

  EnvironmentBlock block;
  std::memset(&block, 0, sizeof block);
  for (std::size_t k = 0; k < count_; ++k) {
    const ShadowedSource& src = s.sources[k];
    boxes_[k] = fit_shadow_box(lo, hi, src.direction);
    block.shadow_view_proj[k] = boxes_[k].view_proj;
    block.source_direction[k] = glm::vec4(glm::normalize(src.direction), src.weight);
    block.source_irradiance[k] = glm::vec4(src.irradiance, 0.0f);
  }
  block.params = glm::vec4(static_cast<float>(count_), s.direct_diffuse ? 1.0f : 0.0f,
                           std::cos(s.rotation_z), std::sin(s.rotation_z));
  const std::vector<glm::vec3> sets = environment_sets(s);
  for (std::size_t i = 0; i < sets.size(); ++i) block.sets[i] = glm::vec4(sets[i], 0.0f);
  next_.clear();
  next_.push_back(size_);
  for (std::size_t k = 0; k < count_; ++k)
    for (int i = 0; i < 3; ++i)
      next_.push_back(std::bit_cast<std::uint32_t>(block.source_direction[k][i]));
  meshes.append_geometry_key(next_);
  stale_ = next_ != key_;
  const Slice slice = ctx.ring.upload(&block, sizeof block);
  bindings_.block = {slice.buffer, slice.offset, sizeof block};
  for (std::size_t k = 0; k < EnvironmentShading::kMaxSources; ++k)
    bindings_.maps[k] = {sampler_.get(), images_[k < count_ ? k : 0].view.get(),
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  active_ = true;
}

void ShadowPass::record(FrameContext& ctx, const MeshPass& meshes) {
  if (!active_ || !stale_) return;
  key_.swap(next_);
  stale_ = false;
  ++renders_;
  const VkPipelineStageFlags2 tests =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  const VkExtent2D extent{size_, size_};
  for (std::size_t k = 0; k < count_; ++k) {
    // The previous frame's mesh-pass reads finish before this frame overwrites the map.
    barrier(ctx.cmd, {images_[k].get(), VK_IMAGE_ASPECT_DEPTH_BIT,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_NONE, tests,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                          VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                      VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL});
    VkRenderingAttachmentInfo depth =
        vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
    depth.imageView = images_[k].view.get();
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth.clearValue.depthStencil = {1.0f, 0};  // farthest from the source: lit
    VkRenderingInfo info = vk_struct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.pDepthAttachment = &depth;
    vkCmdBeginRendering(ctx.cmd, &info);
    set_viewport(ctx.cmd, extent);
    vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
    meshes.draw_depth(ctx.cmd, layout_.get(), boxes_[k].view_proj);
    vkCmdEndRendering(ctx.cmd);
    barrier(ctx.cmd,
            {images_[k].get(), VK_IMAGE_ASPECT_DEPTH_BIT, tests,
             VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
             VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
             VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  }
}

}  // namespace penumbra::render
