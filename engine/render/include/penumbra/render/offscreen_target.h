// OffscreenTarget: headless output, no display or surface needed (tests, CI, the headless main
// job, benchmarks). Frames stay in the renderer's images; Renderer::capture reads one back.
//
// Threading: render thread only.
#pragma once

#include "penumbra/render/target.h"

namespace penumbra::render {

class OffscreenTarget final : public Target {
 public:
  OffscreenTarget(std::uint32_t width, std::uint32_t height);
  // The next frame renders at the new size (0 x 0: frames are skipped, like a minimised window).
  void resize(std::uint32_t width, std::uint32_t height) { extent_ = {width, height}; }

  VkExtent2D extent() const override { return extent_; }
  std::optional<TargetFrame> acquire(std::uint32_t slot) override;
  void record_output(VkCommandBuffer, VkImage, VkExtent2D) override {}
  void present() override {}

 private:
  VkExtent2D extent_;
};

}  // namespace penumbra::render
