#include "penumbra/render/terrain_pass.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>

#if defined(__F16C__)
#include <immintrin.h>
#endif

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

namespace penumbra::render {
namespace {
constexpr VkFormat kLightingFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

struct Push {
  float origin_cell[4];
  float albedo[4];         // as shown: 1 in the lighting-only view
  float lighting_size[4];  // texels of the bound lighting texture (1x1 placeholder: lighting 1)
  std::int32_t grid[4];    // samples along x, along y; chunks along x; quads per chunk side
};

// Sample positions 0, s, 2s, ... along a chunk side of `quads` quads, always ending at `quads`.
std::vector<int> stops(int quads, int stride) {
  std::vector<int> v;
  for (int i = 0; i < quads; i += stride) v.push_back(i);
  v.push_back(quads);
  return v;
}

bool drawable(const std::shared_ptr<const assets::HeightField>& f) {
  return f && f->width >= 2 && f->height >= 2 &&
         f->heights.size() >= static_cast<std::size_t>(f->width) * f->height;
}

bool usable(const Terrain& t) {
  return t.lighting && t.lighting_width > 0 && t.lighting_height > 0 &&
         t.lighting->size() >= static_cast<std::size_t>(t.lighting_width) * t.lighting_height;
}

// RGB floats to RGBA half floats (alpha 1), on the frame's critical path every time the lighting
// changes: with F16C (part of the x86-64-v3 baseline) one conversion instruction per texel,
// about 15x glm::packHalf1x16 (1.3 ms a frame for the demo's 256x256 texels, docs/play.md).
void pack_half_rgba(const glm::vec3* rgb, std::size_t n, std::uint16_t* out) {
#if defined(__F16C__)
  for (std::size_t i = 0; i < n; ++i) {
    const __m128 v = _mm_set_ps(1.0f, rgb[i].z, rgb[i].y, rgb[i].x);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 4 * i),
                     _mm_cvtps_ph(v, _MM_FROUND_TO_NEAREST_INT));
  }
#else
  for (std::size_t i = 0; i < n; ++i) {
    out[4 * i + 0] = glm::packHalf1x16(rgb[i].x);
    out[4 * i + 1] = glm::packHalf1x16(rgb[i].y);
    out[4 * i + 2] = glm::packHalf1x16(rgb[i].z);
    out[4 * i + 3] = glm::packHalf1x16(1.0f);
  }
#endif
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
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr}};
  layout_ = create_pipeline_layout(device, bindings, sizeof(Push));
  PipelineDesc d;
  d.vertex = Shader::kTerrainVert;
  d.fragment = Shader::kTerrainFrag;
  d.layout = layout_.get();
  d.color_format = color_format;
  d.depth_format = depth_format;
  d.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP;
  d.primitive_restart = false;  // strips joined by degenerate triangles (draw())
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

float TerrainPass::chunk_error(const assets::HeightField& f, int x0, int y0, int qw, int qh,
                               int stride) {
  if (stride <= 1) return 0.0f;
  const std::vector<int> xs = stops(qw, stride), ys = stops(qh, stride);
  float error = 0.0f;
  for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
      // The coarse quad's triangles (as the strips draw them): diagonal from (xa, ya) to (xb, yb).
      const int xa = x0 + xs[i], xb = x0 + xs[i + 1], ya = y0 + ys[j], yb = y0 + ys[j + 1];
      const float ha = f.at(xa, ya), hb = f.at(xb, ya), hc = f.at(xa, yb), hd = f.at(xb, yb);
      for (int y = ya; y <= yb; ++y) {
        const float v = static_cast<float>(y - ya) / static_cast<float>(yb - ya);
        for (int x = xa; x <= xb; ++x) {
          const float u = static_cast<float>(x - xa) / static_cast<float>(xb - xa);
          const float h =
              v >= u ? ha + v * (hc - ha) + u * (hd - hc) : ha + u * (hb - ha) + v * (hd - hb);
          error = std::max(error, std::abs(f.at(x, y) - h));
        }
      }
    }
  }
  return error;
}

void TerrainPass::upload_heights(FrameContext& ctx, const assets::HeightField& f) {
  const VkDeviceSize bytes = static_cast<VkDeviceSize>(f.width) * f.height * sizeof(float);
  // Chunks: height range (frustum culling, skirt depth) and geometric error per level.
  chunks_.clear();
  std::vector<std::pair<int, int>> shapes;
  chunks_x_ = (f.width - 2) / kChunkQuads + 1;
  chunks_y_ = (f.height - 2) / kChunkQuads + 1;
  for (int y0 = 0; y0 + 1 < f.height; y0 += kChunkQuads) {
    for (int x0 = 0; x0 + 1 < f.width; x0 += kChunkQuads) {
      Chunk c{};
      c.x0 = x0;
      c.y0 = y0;
      c.qw = std::min(kChunkQuads, f.width - 1 - x0);
      c.qh = std::min(kChunkQuads, f.height - 1 - y0);
      auto it = std::find(shapes.begin(), shapes.end(), std::make_pair(c.qw, c.qh));
      if (it == shapes.end()) it = shapes.insert(shapes.end(), {c.qw, c.qh});
      c.shape = static_cast<int>(it - shapes.begin());
      c.hmin = c.hmax = f.at(x0, y0);
      for (int y = y0; y <= y0 + c.qh; ++y)
        for (int x = x0; x <= x0 + c.qw; ++x) {
          c.hmin = std::min(c.hmin, f.at(x, y));
          c.hmax = std::max(c.hmax, f.at(x, y));
        }
      for (int level = 0; level < kLods; ++level)
        c.error[level] = chunk_error(f, x0, y0, c.qw, c.qh, 1 << level);
      chunks_.push_back(c);
    }
  }
  if (f.width != grid_w_ || f.height != grid_h_) {
    if (heights_.size) ctx.retire.retire(ctx.frame, std::move(heights_));
    heights_ =
        create_buffer(ctx.device, bytes,
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
    build_patterns(f.width, shapes);
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

void TerrainPass::build_patterns(int grid_width, const std::vector<std::pair<int, int>>& shapes) {
  // Triangle strips per chunk shape, level and part. A surface entry is the sample's offset
  // from the chunk's first sample (ly * width + lx); a skirt's lowered entry is kLowered | its
  // chunk-local index (ly * (kChunkQuads + 1) + lx), which draw() turns into the vertex the
  // shader lowers by that chunk's skirt depth.
  const auto w = static_cast<std::uint32_t>(grid_width);
  patterns_.clear();
  ranges_.assign(shapes.size(), {});
  auto at = [&](int x, int y) {
    return static_cast<std::uint32_t>(y) * w + static_cast<std::uint32_t>(x);
  };
  auto lowered = [](int x, int y) {
    return kLowered | static_cast<std::uint32_t>(y * (kChunkQuads + 1) + x);
  };
  for (std::size_t shape = 0; shape < shapes.size(); ++shape) {
    for (int level = 0; level < kLods; ++level) {
      const std::vector<int> xs = stops(shapes[shape].first, 1 << level);
      const std::vector<int> ys = stops(shapes[shape].second, 1 << level);
      auto& parts = ranges_[shape][level];
      auto strip = [&](Range& r, std::size_t n, auto vertex_pair) {
        for (std::size_t i = 0; i < n; ++i) {
          const auto [a, b] = vertex_pair(i);
          patterns_.insert(patterns_.end(), {a, b});
        }
        patterns_.push_back(kRestart);
        r.triangles += static_cast<std::uint32_t>(2 * n - 2);
      };
      auto part = [&](Part p, auto fill) {
        parts[p].first = static_cast<std::uint32_t>(patterns_.size());
        fill(parts[p]);
        parts[p].count = static_cast<std::uint32_t>(patterns_.size()) - parts[p].first;
      };
      part(kSurface, [&](Range& r) {
        for (std::size_t row = 0; row + 1 < ys.size(); ++row)
          strip(r, xs.size(), [&](std::size_t i) {
            return std::make_pair(at(xs[i], ys[row + 1]), at(xs[i], ys[row]));
          });
      });
      // Skirts face out of their chunk (counter-clockwise seen from outside, as the surface is
      // seen from above), so back-face culling keeps, at each seam, the skirt of the chunk
      // beyond it: the one that can show through the crack.
      const std::pair<Part, int> rows[] = {{kSkirtLow, ys.front()}, {kSkirtHigh, ys.back()}};
      for (const auto& row : rows) {
        const int edge_y = row.second;  // not a structured binding: clang 14 cannot capture those
        const bool flip = row.first == kSkirtHigh;
        part(row.first, [&](Range& r) {
          strip(r, xs.size(), [&](std::size_t i) {
            const std::uint32_t top = at(xs[i], edge_y), low = lowered(xs[i], edge_y);
            return flip ? std::make_pair(low, top) : std::make_pair(top, low);
          });
        });
      }
      const std::pair<Part, int> cols[] = {{kSkirtLeft, xs.front()}, {kSkirtRight, xs.back()}};
      for (const auto& col : cols) {
        const int edge_x = col.second;
        const bool flip = col.first == kSkirtLeft;
        part(col.first, [&](Range& r) {
          strip(r, ys.size(), [&](std::size_t i) {
            const std::uint32_t top = at(edge_x, ys[i]), low = lowered(edge_x, ys[i]);
            return flip ? std::make_pair(low, top) : std::make_pair(top, low);
          });
        });
      }
    }
  }
}

void TerrainPass::upload_lighting(FrameContext& ctx, const Terrain& t) {
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
  pack_half_rgba(rgb.data(), n, texels_.data());
  copy_to_image(ctx.cmd, ctx.ring, texels_.data(), texels_.size() * sizeof(std::uint16_t),
                lighting_, old_layout);
}

void TerrainPass::prepare(FrameContext& ctx) {
  const Terrain& t = ctx.packet.terrain;
  if (!drawable(t.heights)) {
    heights_src_.reset();
  } else if (t.heights != heights_src_) {
    upload_heights(ctx, *t.heights);
    heights_src_ = t.heights;
  }
  if (!usable(t)) {
    lighting_src_.reset();
  } else if (t.lighting != lighting_src_ || t.lighting_width != lit_w_ ||
             t.lighting_height != lit_h_) {
    upload_lighting(ctx, t);
    lit_w_ = t.lighting_width;
    lit_h_ = t.lighting_height;
    lighting_src_ = t.lighting;
  }
}

int TerrainPass::select_level(const float (&error)[kLods], float distance, float focal_px,
                              float max_pixels) {
  if (max_pixels <= 0.0f) return 0;
  for (int level = kLods - 1; level > 0; --level)
    if (error[level] * focal_px <= max_pixels * distance) return level;
  return 0;
}

float TerrainPass::vertical_error_distance(const glm::vec3& eye, const glm::vec3& lo,
                                           const glm::vec3& hi) {
  // A vertical offset e at a point p seen from the eye moves on screen by about
  // e * sin(beta) * focal / |p - eye|, beta the angle between the view ray and the vertical:
  // e * focal * h / (h^2 + z^2) with h, z the horizontal and vertical parts of p - eye. Over the
  // box, h / (h^2 + z^2) is largest at the smallest |z|, and then at h = |z| (or the end of h's
  // range nearest to it). The return value is the reciprocal of that largest value.
  const float z = std::max({lo.z - eye.z, eye.z - hi.z, 0.0f});
  const glm::vec2 e(eye);
  const float h_min = glm::length(glm::clamp(e, glm::vec2(lo), glm::vec2(hi)) - e);
  const float far_x = std::max(std::abs(lo.x - e.x), std::abs(hi.x - e.x));
  const float far_y = std::max(std::abs(lo.y - e.y), std::abs(hi.y - e.y));
  const float h_max = std::sqrt(far_x * far_x + far_y * far_y);
  const float h = std::clamp(z, h_min, h_max);
  if (h <= 0.0f) return 0.0f;  // the eye is in the box
  return (h * h + z * z) / h;
}

void TerrainPass::draw(FrameContext& ctx) {
  triangles_ = 0;
  chunks_drawn_ = chunks_culled_ = 0;
  if (!heights_src_) return;
  const Terrain& t = ctx.packet.terrain;
  const float cell = heights_src_->cell_size;
  const glm::vec3 eye = ctx.packet.camera.position;

  // Visibility (frustum) and level of every chunk first: skirts depend on the neighbours'.
  for (Chunk& c : chunks_) {
    const float depth = std::max(c.hmax - c.hmin, cell);
    const glm::vec3 lo = t.origin + glm::vec3(c.x0 * cell, c.y0 * cell, c.hmin - depth);
    const glm::vec3 hi = t.origin + glm::vec3((c.x0 + c.qw) * cell, (c.y0 + c.qh) * cell, c.hmax);
    // Clip-space test: culled when all 8 corners are outside one plane.
    bool outside[6] = {true, true, true, true, true, true};
    for (int k = 0; k < 8; ++k) {
      const glm::vec4 p = ctx.view_proj * glm::vec4(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y,
                                                    k & 4 ? hi.z : lo.z, 1.0f);
      const float d[6] = {p.w + p.x, p.w - p.x, p.w + p.y, p.w - p.y, p.z, p.w - p.z};
      for (int i = 0; i < 6; ++i) outside[i] = outside[i] && d[i] < 0.0f;
    }
    c.visible = std::find(std::begin(outside), std::end(outside), true) == std::end(outside);
    const glm::vec3 surface_lo(lo.x, lo.y, t.origin.z + c.hmin);
    c.level = select_level(c.error, vertical_error_distance(eye, surface_lo, hi), ctx.focal_px,
                           ctx.packet.view.terrain_lod_pixels);
  }

  // Every visible chunk's strips go into one index list for one draw (lavapipe pays about
  // 20 us per draw call, which at 16x16-quad chunks would cost more than the triangles saved).
  // A skirt where a visible neighbour is drawn at another level: along the shared edge each
  // side is within its own geometric error of the true samples, so the crack is at most the sum
  // of the two errors. The skirt hangs that deep (plus 1% of a cell against rounding), not the
  // chunk's height range, so where the terrain's outer edge shows it from the side it stays
  // within the pixel budget.
  const auto samples = static_cast<std::uint32_t>(grid_w_ * grid_h_);
  constexpr std::uint32_t kChunkVertices = (kChunkQuads + 1) * (kChunkQuads + 1);
  frame_indices_.clear();
  bool new_strip = true;
  skirt_depths_.assign(chunks_.size(), 0.0f);
  for (int cy = 0; cy < chunks_y_; ++cy) {
    for (int cx = 0; cx < chunks_x_; ++cx) {
      const std::size_t ci = static_cast<std::size_t>(cy) * chunks_x_ + cx;
      const Chunk& c = chunks_[ci];
      if (!c.visible) {
        ++chunks_culled_;
        continue;
      }
      const Chunk* neighbours[4] = {nullptr, nullptr, nullptr, nullptr};  // low, high, left, right
      const int offsets[4][2] = {{0, -1}, {0, 1}, {-1, 0}, {1, 0}};
      float neighbour_error = 0.0f;
      for (int k = 0; k < 4; ++k) {
        const int nx = cx + offsets[k][0], ny = cy + offsets[k][1];
        if (nx < 0 || ny < 0 || nx >= chunks_x_ || ny >= chunks_y_) continue;
        const Chunk& n = chunks_[static_cast<std::size_t>(ny) * chunks_x_ + nx];
        if (!n.visible || n.level == c.level) continue;
        neighbours[k] = &n;
        neighbour_error = std::max(neighbour_error, n.error[n.level]);
      }
      skirt_depths_[ci] = c.error[c.level] + neighbour_error + 0.01f * cell;
      const auto& parts = ranges_[c.shape][c.level];
      const auto base = static_cast<std::uint32_t>(c.y0 * grid_w_ + c.x0);
      const auto skirt_base = samples + static_cast<std::uint32_t>(ci) * kChunkVertices;
      auto append = [&](Part p) {
        const std::uint32_t* first = patterns_.data() + parts[p].first;
        for (const std::uint32_t* i = first; i != first + parts[p].count; ++i) {
          if (*i == kRestart) {
            new_strip = true;
            continue;
          }
          const std::uint32_t v = *i & kLowered ? skirt_base + (*i & ~kLowered) : base + *i;
          if (new_strip && !frame_indices_.empty()) {
            // Joined by degenerate triangles: the last vertex again, the first one again, and
            // once more where needed so that the new strip starts at an even position.
            const std::uint32_t last = frame_indices_.back();
            frame_indices_.push_back(last);
            frame_indices_.push_back(v);
            if (frame_indices_.size() % 2 == 1) frame_indices_.push_back(v);
          }
          new_strip = false;
          frame_indices_.push_back(v);
        }
        triangles_ += parts[p].triangles;
      };
      append(kSurface);
      const Part skirts[4] = {kSkirtLow, kSkirtHigh, kSkirtLeft, kSkirtRight};
      for (int k = 0; k < 4; ++k)
        if (neighbours[k]) append(skirts[k]);
      ++chunks_drawn_;
    }
  }
  if (frame_indices_.empty()) return;

  const Slice indices =
      ctx.ring.upload(frame_indices_.data(), frame_indices_.size() * sizeof(std::uint32_t));
  const Slice depths = ctx.ring.upload(skirt_depths_.data(), skirt_depths_.size() * sizeof(float));
  vkCmdBindPipeline(ctx.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
  const VkDescriptorBufferInfo heights{heights_.get(), 0, VK_WHOLE_SIZE};
  const VkDescriptorBufferInfo skirt{depths.buffer, depths.offset, depths.size};
  const VkDescriptorImageInfo image{sampler_.get(),
                                    lighting_src_ ? lighting_.view.get() : placeholder_.view.get(),
                                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  const VkWriteDescriptorSet writes[] = {
      buffer_write(0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ctx.camera),
      buffer_write(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &heights), image_write(2, &image),
      buffer_write(3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &skirt)};
  push_descriptors(*device_, ctx.cmd, layout_.get(), writes);
  const glm::vec3 albedo = ctx.packet.view.lighting_only ? glm::vec3(1.0f) : t.albedo;
  const float lit_w = lighting_src_ ? static_cast<float>(lit_w_) : 1.0f;
  const float lit_h = lighting_src_ ? static_cast<float>(lit_h_) : 1.0f;
  Push push{{t.origin.x, t.origin.y, t.origin.z, cell},
            {albedo.x, albedo.y, albedo.z, 0.0f},
            {lit_w, lit_h, 0.0f, 0.0f},
            {grid_w_, grid_h_, chunks_x_, kChunkQuads}};
  vkCmdPushConstants(ctx.cmd, layout_.get(),
                     VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                     &push);
  vkCmdBindIndexBuffer(ctx.cmd, indices.buffer, indices.offset, VK_INDEX_TYPE_UINT32);
  vkCmdDrawIndexed(ctx.cmd, static_cast<std::uint32_t>(frame_indices_.size()), 1, 0, 0, 0);
}

}  // namespace penumbra::render
