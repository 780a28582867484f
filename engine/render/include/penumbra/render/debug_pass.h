// Debug primitives pass (shaders/debug.glsl): wire spheres (blockers), lines (probe
// tetrahedra), points (probes, particles), unlit and depth-tested, in HDR colours.
//
// Per frame the packet's lists are copied into the upload ring: points as they are (position +
// colour), lines as two such vertices, spheres as per-instance data (centre, radius, colour)
// of an instanced unit wire sphere (three great circles, kSegments segments each) uploaded once.
//
// Threading: render thread only.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/render/pass_context.h"
#include "penumbra/render/pipeline.h"

namespace penumbra::render {

class DebugPass {
 public:
  static constexpr std::uint32_t kSegments = 48;

  DebugPass(Device& device, VkFormat color_format, VkFormat depth_format);
  void prepare(FrameContext& ctx);
  void draw(FrameContext& ctx);

 private:
  Device* device_;
  PipelineLayout layout_;
  Unique<VkPipeline> lines_;
  Unique<VkPipeline> points_;
  Unique<VkPipeline> spheres_;
  Buffer unit_sphere_;
  std::uint32_t unit_vertices_ = 0;
  Slice line_data_, point_data_, sphere_data_;
  std::uint32_t line_vertices_ = 0, point_count_ = 0, sphere_count_ = 0;
  std::vector<PointDraw> scratch_;
};

}  // namespace penumbra::render
