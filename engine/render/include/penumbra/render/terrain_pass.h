// Terrain pass (shaders/terrain.glsl): the height field as a grid of triangles, shaded with the
// per-texel lighting texture times the albedo.
//
// Level of detail: a right-triangle bintree (terrain_bintree.h) refined each frame until every
// triangle's vertical error projects to at most ViewSettings::terrain_lod_pixels (0: full
// detail) and culled to the view frustum. Its mesh has no T-junctions, so no cracks and no
// skirts; all its triangles go into one index list and one draw call per frame (on lavapipe a
// draw costs about 20 us). The lighting is a texture sampled per pixel, so coarser geometry keeps
// the full lighting detail; only the shape moves, by at most that many pixels (the budget and
// why: docs/play.md). Back faces are culled: slopes facing away are hidden by the terrain in
// front.
//
// GPU data, re-uploaded only when the packet's pointers change: heights (storage buffer, one
// float per sample; vertices come from gl_VertexIndex) and the lighting texture (RGBM in RGBA8, lighting_texels.h); the
// bintree is rebuilt with the heights. Per frame, through the upload ring: the index list.
// Same-size updates are copied in place (ordered after the previous frame's reads by barriers);
// size changes create new resources and retire the old ones.
//
// Threading: render thread only.
#pragma once

#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>

#include "penumbra/render/pass_context.h"
#include "penumbra/render/pipeline.h"
#include "penumbra/render/terrain_bintree.h"

namespace penumbra::render {

class TerrainPass {
 public:
  TerrainPass(Device& device, VkFormat color_format, VkFormat depth_format);
  void prepare(FrameContext& ctx);
  void draw(FrameContext& ctx);
  // Triangles drawn by the last draw().
  std::uint64_t triangles() const { return triangles_; }

 private:
  void upload_heights(FrameContext& ctx, const data::HeightField& field);
  void upload_lighting(FrameContext& ctx, const TerrainDraw& terrain);

  Device* device_;
  PipelineLayout layout_;
  Unique<VkPipeline> pipeline_;
  Unique<VkSampler> sampler_;
  Image placeholder_;  // 1x1, bound when there is no lighting texture

  Buffer heights_;
  int grid_w_ = 0, grid_h_ = 0;
  TerrainBintree bintree_;
  std::vector<std::uint32_t> frame_indices_;  // this frame's draw, uploaded through the ring
  Image lighting_;
  int lit_w_ = 0, lit_h_ = 0;
  std::shared_ptr<const data::HeightField> heights_src_;
  std::shared_ptr<const std::vector<glm::vec3>> lighting_src_;
  std::vector<std::uint8_t> texels_;  // conversion scratch
  float lighting_scale_ = 1.0f;       // RGBM decode scale of lighting_
  std::uint64_t triangles_ = 0;
};

}  // namespace penumbra::render
