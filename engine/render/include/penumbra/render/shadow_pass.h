// Shadow pass (shaders/shadow.glsl): one directional shadow map per environment light source
// ([Ambrosj16] sec. 3.6, 4.3), for the mesh pass's per-pixel environment shading
// (EnvironmentShading in packet.h; docs/environment.md "Renderer").
//
// Per frame, when the packet's environment shading is enabled, valid (check_environment_
// shading) and has sources and meshes: for each of the first EnvironmentShading::kMaxSources
// sources, a depth-only render of every mesh into a D32 map, orthographic along the source
// (fit_shadow_box), front faces culled (back faces stored, against Peter Panning). Then the
// EnvironmentBlock (shaders/mesh.glsl) is written to the frame's upload ring: the maps'
// matrices, the sources, and the OEM sets the mesh pass may pick, as radiance per unit albedo
// (environment_sets). Otherwise nothing is recorded and bindings() is null: the mesh pass is
// today's. The terrain is neither a caster nor a receiver here (its key light is per texel).
//
// The maps are shared by the frames in flight (like FrameImages: one queue, each frame's first
// barrier waits for the previous frame's reads); they are recreated when the count or the
// size changes. They are re-rendered only when what they show changes: the map size, a
// source's direction, or a mesh drawn, its transform or the draw order (MeshPass::
// append_geometry_key); otherwise the last frame's maps are read again.
//
// Threading: render thread only; the free functions are pure (any thread).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "penumbra/render/pass_context.h"
#include "penumbra/render/pipeline.h"

namespace penumbra::render {

class MeshPass;

// Empty when `s` can be drawn (or is disabled); otherwise why not, naming the field:
// "environment.oem_sh: 20 floats, expected 54 (2^1 sets x 27)". Checked: oem_source_count
// 1..8 with sources, the sets' size and finiteness, every source's oem_bit (< count, distinct,
// not in present_mask), direction (finite, non-zero), irradiance (finite, >= 0), weight (in
// [0, 1]), present_mask < 2^count.
std::string check_environment_shading(const EnvironmentShading& s);

// The orthographic shadow box of a source: the world AABB [lo, hi] seen along -direction
// (from the source), its 8 corners' extent in the light's frame padded by 1% (at least 1 mm)
// on each side. view_proj maps world to clip: x, y in [-1, 1] across the box, z in [0, 1]
// from the side nearest the source. Finite for any unit direction (zenith and horizon
// included) and any box (a point gets a 1 mm box). `direction` need not be normalised; zero or
// non-finite gives the identity with extent 0 (callers check first).
struct ShadowBox {
  glm::mat4 view_proj{1.0f};
  glm::vec3 extent{0.0f};  // metres: width, height, depth of the box
};
ShadowBox fit_shadow_box(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& direction);

// The OEM sets the mesh shader indexes by its visibility mask V (bit k: sources[k] seen,
// k < K = min(sources, kMaxSources)): 2^K sets x 9 coefficients x RGB, each the 3-band SH of
// radiance per unit albedo (the clamped-cosine convolution A_l / pi of [Ramamoorthi01] eq. 8
// applied: 1, 2/3, 1/4), so the shader's diffuse light is sum_i c_i y_i(n).
//   direct_diffuse: every set is the OEM with all K sources removed (present_mask only);
//   otherwise set V is the weight-blended OEM of "sources in V present": sum over U in V of
//   prod_{k in U} w_k prod_{k in V \ U} (1 - w_k) OEM(present_mask | bits of U).
// Needs a valid `s` (check_environment_shading) with sources.
std::vector<glm::vec3> environment_sets(const EnvironmentShading& s);

class ShadowPass {
 public:
  explicit ShadowPass(Device& device);
  // After MeshPass::prepare (needs its draws and bounds): decides, writes the block.
  void prepare(FrameContext& ctx, const MeshPass& meshes);
  // Outside any rendering scope: the depth renders and their barriers (nothing when inactive
  // or when the maps already show this frame's scene: stale() false).
  void record(FrameContext& ctx, const MeshPass& meshes);
  bool stale() const { return active_ && stale_; }
  // What the mesh pass binds this frame; null when the environment shading is off.
  const EnvironmentBindings* bindings() const { return active_ ? &bindings_ : nullptr; }
  std::size_t maps() const { return active_ ? count_ : 0; }
  std::uint64_t renders() const { return renders_; }   // frames that re-rendered the maps
  const std::string& error() const { return error_; }  // the last packet's check, "" if fine
  const ShadowBox& box(std::size_t k) const { return boxes_[k]; }

 private:
  Device* device_;
  PipelineLayout layout_;
  Unique<VkPipeline> pipeline_;
  Unique<VkSampler> sampler_;
  std::vector<Image> images_;
  std::uint32_t size_ = 0;
  std::size_t count_ = 0;
  bool active_ = false;
  bool stale_ = true;                // the maps do not show this frame's scene
  std::vector<std::uint64_t> key_;   // what the maps show (sources, size, geometry)
  std::vector<std::uint64_t> next_;  // this frame's
  std::array<ShadowBox, EnvironmentShading::kMaxSources> boxes_{};
  EnvironmentBindings bindings_{};
  std::string error_;
  std::uint64_t renders_ = 0;
};

}  // namespace penumbra::render
