// Tonemap pass (shaders/tonemap.glsl): reads the HDR image (SHADER_READ_ONLY_OPTIMAL) and
// writes the LDR image: radiance * 2^exposure_ev, then the filmic curve (Hejl / Burgess-Dawson,
// display-encoded) or a clamp with exact sRGB encoding. Drawn inside a rendering scope on the
// LDR image.
//
// Threading: render thread only.
#pragma once

#include "penumbra/render/packet.h"
#include "penumbra/render/pipeline.h"

namespace penumbra::render {

class TonemapPass {
 public:
  TonemapPass(Device& device, VkFormat ldr_format);
  void draw(VkCommandBuffer cmd, const Image& hdr, const ViewSettings& view);

 private:
  Device* device_;
  PipelineLayout layout_;
  Unique<VkPipeline> pipeline_;
  Unique<VkSampler> sampler_;
};

}  // namespace penumbra::render
