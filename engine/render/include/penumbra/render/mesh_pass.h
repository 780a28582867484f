// Mesh pass (shaders/mesh.glsl): triangle meshes with a model matrix and per-vertex lighting.
//
// Geometry cache: a MeshData is uploaded once (positions + normals interleaved, 32-bit
// indices, one device-local buffer each) the first frame a draw references it, and kept while
// draws keep referencing it; the cache holds the shared_ptr, so the address it is keyed by
// cannot be reused while cached. An entry unused for kEvictAfterFrames frames is retired.
// Vertex lighting (per-frame data) is copied into the frame's upload ring each frame and bound
// as a second vertex stream (fewer values than positions: the preview shading instead). A mesh
// whose indices are out of range is rejected at upload (not drawn, counted in rejected()).
// Back faces are culled: counter-clockwise triangles seen from outside are front faces (glTF).
//
// Environment shading (EnvironmentShading in packet.h): when FrameContext::environment is set
// (the shadow pass made its maps this frame), every mesh is drawn with the mesh_env shaders
// (MESH_ENVIRONMENT in shaders/mesh.glsl: shadow-map tests, OEM set, direct and Blinn terms)
// instead of the vertex-lit or preview variants. draw_depth() draws the same geometry for the
// shadow pass, and bounds() is the world box of this frame's draws (the shadow box's input).
//
// Threading: render thread only.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "penumbra/render/pass_context.h"
#include "penumbra/render/pipeline.h"

namespace penumbra::render {

class MeshPass {
 public:
  static constexpr std::uint64_t kEvictAfterFrames = 8;

  MeshPass(Device& device, VkFormat color_format, VkFormat depth_format);
  void prepare(FrameContext& ctx);
  void draw(FrameContext& ctx);
  // Every drawn mesh's geometry (positions only) with push constant view_proj * transform, in
  // the caller's bound pipeline (layout: one mat4 push constant, no descriptors).
  void draw_depth(VkCommandBuffer cmd, VkPipelineLayout layout, const glm::mat4& view_proj) const;
  // The world AABB of this frame's draws (each mesh's local box, transformed); false: none.
  bool bounds(glm::vec3& lo, glm::vec3& hi) const;
  // Appends what draw_depth() draws this frame (each mesh's address and transform, in draw
  // order) to `key`: equal keys draw the same depth.
  void append_geometry_key(std::vector<std::uint64_t>& key) const;

  std::size_t cached_meshes() const { return cache_.size(); }
  std::size_t rejected() const { return rejected_; }
  std::uint64_t triangles() const { return triangles_; }  // drawn in the last frame

 private:
  struct GpuMesh {
    std::shared_ptr<const data::MeshData> source;
    Buffer vertices;
    Buffer indices;
    std::uint32_t index_count = 0;
    std::uint32_t vertex_count = 0;
    glm::vec3 lo{0.0f}, hi{0.0f};  // object-space bounds
    std::uint64_t last_used = 0;
    bool valid = false;
  };
  struct Draw {
    const GpuMesh* mesh;
    const MeshDraw* draw;
    Slice lighting;  // buffer == VK_NULL_HANDLE: none
  };
  void draw_environment(FrameContext& ctx);
  GpuMesh upload(FrameContext& ctx, const std::shared_ptr<const data::MeshData>& mesh);

  Device* device_;
  PipelineLayout layout_;
  Unique<VkPipeline> preview_;  // variant 0: no vertex lighting
  Unique<VkPipeline> lit_;      // variant 1: vertex lighting
  PipelineLayout env_layout_;   // camera, EnvironmentBlock, shadow maps
  // The environment shading (mesh_env shaders), variant = source count (1-3) + 4 x direct
  // diffuse, each made on first use.
  Unique<VkPipeline> env_[8];
  PipelineDesc env_desc_;
  std::unordered_map<const data::MeshData*, GpuMesh> cache_;
  std::vector<Draw> draws_;
  std::vector<float> scratch_;
  glm::vec3 lo_{0.0f}, hi_{0.0f};
  bool have_bounds_ = false;
  std::size_t rejected_ = 0;
  std::uint64_t triangles_ = 0;
};

}  // namespace penumbra::render
