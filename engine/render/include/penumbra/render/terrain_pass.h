// Terrain pass (shaders/terrain.glsl): the height field as a grid of triangles, shaded with the
// per-texel lighting texture times the albedo.
//
// Chunks and level of detail (geomipmapping): the grid is cut into chunks of kChunkQuads x
// kChunkQuads quads. At upload, each chunk gets, for every vertex stride s in {1, 2, ..., 16},
// its geometric error: the largest vertical distance between a height sample and the surface
// drawn with stride s. Each frame, chunks outside the view frustum are skipped and every other
// chunk is drawn with the coarsest stride whose error, seen from the camera, projects to at most
// ViewSettings::terrain_lod_pixels (0: always full detail). The projection accounts for the
// error being vertical (vertical_error_distance): seen from above it moves less on screen than
// seen edge-on. The lighting is a texture sampled per pixel, so coarser geometry keeps the full
// lighting detail; only the shape moves, by less than that many pixels (the budget and why:
// docs/play.md). Between two visible neighbours of different strides, both draw a vertical
// skirt along their shared edge, as deep as the two errors together (the largest the crack can
// be), which covers the crack. Skirts face out of their chunk and back faces are culled, so at a
// seam only the skirt that can show through the crack is rasterised. All visible chunks go into
// one index list and one draw call per frame, as one triangle strip whose pieces are joined by
// degenerate triangles: on lavapipe a draw costs about 20 us, and small chunks adapt better to
// rough terrain.
//
// GPU data, re-uploaded only when the packet's pointers change: heights (storage buffer, one
// float per sample; vertices come from gl_VertexIndex) and the lighting texture (RGBA16F). Per
// frame, through the upload ring: the index list (from CPU-side triangle-strip patterns per
// chunk shape and stride, rebuilt only when the grid size changes) and the chunks' skirt depths.
// Same-size updates are copied in place (ordered after the previous frame's reads by barriers);
// size changes create new resources and retire the old ones.
//
// Threading: render thread only.
#pragma once

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>

#include "penumbra/render/pass_context.h"
#include "penumbra/render/pipeline.h"

namespace penumbra::render {

class TerrainPass {
 public:
  static constexpr int kChunkQuads = 16;
  static constexpr int kLods = 6;

  TerrainPass(Device& device, VkFormat color_format, VkFormat depth_format);
  void prepare(FrameContext& ctx);
  void draw(FrameContext& ctx);
  // Triangles drawn and chunks drawn / culled by the last draw() (skirts included).
  std::uint64_t triangles() const { return triangles_; }
  std::uint32_t chunks_drawn() const { return chunks_drawn_; }
  std::uint32_t chunks_culled() const { return chunks_culled_; }

  // The level (stride 1 << level) for a chunk with per-level geometric errors `error` (metres;
  // error[0] = 0) whose nearest point is `distance` away: the coarsest whose error projects to
  // at most `max_pixels` (focal_px: pixels per unit of tan(angle)). max_pixels <= 0: level 0.
  static int select_level(const float (&error)[kLods], float distance, float focal_px,
                          float max_pixels);
  // The distance to use in select_level for a chunk whose surface spans the box [lo, hi] seen
  // from `eye`: the smallest |p - eye|^2 / h over the box (h: horizontal part of p - eye), so
  // that a vertical error e shows as at most e * focal_px / distance pixels (a vertical error
  // seen from above moves less on screen than one seen edge-on). 0 when the eye is in the box.
  static float vertical_error_distance(const glm::vec3& eye, const glm::vec3& lo,
                                       const glm::vec3& hi);
  // Geometric error of drawing `field`'s chunk at (x0, y0), of qw x qh quads, with `stride`.
  static float chunk_error(const assets::HeightField& field, int x0, int y0, int qw, int qh,
                           int stride);

 private:
  struct Chunk {
    int x0, y0;  // first sample
    int qw, qh;  // quads
    int shape;   // index into ranges_
    float hmin, hmax;
    float error[kLods];
    int level = 0;         // this frame's
    bool visible = false;  // this frame's
  };
  struct Range {
    std::uint32_t first = 0, count = 0, triangles = 0;
  };
  enum Part { kSurface, kSkirtLow, kSkirtHigh, kSkirtLeft, kSkirtRight, kParts };
  void upload_heights(FrameContext& ctx, const assets::HeightField& field);
  void upload_lighting(FrameContext& ctx, const Terrain& terrain);

  Device* device_;
  PipelineLayout layout_;
  Unique<VkPipeline> pipeline_;
  Unique<VkSampler> sampler_;
  Image placeholder_;  // 1x1, bound when there is no lighting texture
  static constexpr std::uint32_t kRestart = 0xFFFFFFFFu;  // pattern entry: the strip ends
  static constexpr std::uint32_t kLowered = 0x40000000u;  // pattern entry: a skirt's lower vertex
  void build_patterns(int grid_width, const std::vector<std::pair<int, int>>& shapes);

  Buffer heights_;
  int grid_w_ = 0, grid_h_ = 0;
  std::vector<Chunk> chunks_;
  int chunks_x_ = 0, chunks_y_ = 0;
  // Per chunk shape, level and part (surface; skirts along y0, y0+qh, x0, x0+qw).
  std::vector<std::array<std::array<Range, kParts>, kLods>> ranges_;
  std::vector<std::uint32_t> patterns_;       // the strips ranges_ points into (build_patterns)
  std::vector<std::uint32_t> frame_indices_;  // this frame's draw, uploaded through the ring
  std::vector<float> skirt_depths_;           // this frame's, per chunk (shader binding 3)
  Image lighting_;
  int lit_w_ = 0, lit_h_ = 0;
  std::shared_ptr<const assets::HeightField> heights_src_;
  std::shared_ptr<const std::vector<glm::vec3>> lighting_src_;
  std::vector<std::uint16_t> texels_;  // conversion scratch
  std::uint64_t triangles_ = 0;
  std::uint32_t chunks_drawn_ = 0, chunks_culled_ = 0;
};

}  // namespace penumbra::render
