// Sky pass (shaders/sky.glsl): radiance of the environment map or the procedural sky where no
// geometry was drawn (a full-screen triangle at the far plane, depth-tested, drawn last among
// the scene passes).
//
// The environment map is uploaded as RGBA16F when Sky::environment changes pointer (through a
// temporary staging buffer and a blocking submit: maps are large and change rarely); with no
// map, a 1x1 placeholder is bound and the procedural sky is used.
//
// Threading: render thread only.
#pragma once

#include <memory>

#include "penumbra/render/pass_context.h"
#include "penumbra/render/pipeline.h"

namespace penumbra::render {

class SkyPass {
 public:
  SkyPass(Device& device, VkFormat color_format, VkFormat depth_format);
  void prepare(FrameContext& ctx);
  void draw(FrameContext& ctx);
  bool has_environment() const { return static_cast<bool>(uploaded_); }

 private:
  Device* device_;
  PipelineLayout layout_;
  Unique<VkPipeline> procedural_;            // variant 0
  Unique<VkPipeline> environment_pipeline_;  // variant 1
  Unique<VkSampler> sampler_;
  Image placeholder_;
  Image environment_;
  std::shared_ptr<const data::EnvironmentMap> uploaded_;
};

}  // namespace penumbra::render
