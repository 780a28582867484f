// FrameImages: the offscreen HDR target every frame renders into, whatever the output.
//
//   hdr   R16G16B16A16_SFLOAT  colour attachment of the scene passes, sampled by the tonemap
//   depth D32_SFLOAT           reversed depth (camera.h)
//   ldr   R8G8B8A8_UNORM       tonemapped, sRGB-encoded; the overlay draws on it; it is then
//                              copied to the window's swapchain image and/or read back as PNG
//
// One set serves all frames in flight: frames execute in submission order on the one queue
// and each frame's first barriers wait for the previous frame's use of the images.
//
// Threading: render thread only.
#pragma once

#include <cstdint>

#include "penumbra/render/resources.h"

namespace penumbra::render {

struct FrameImages {
  static constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
  static constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
  static constexpr VkFormat kLdrFormat = VK_FORMAT_R8G8B8A8_UNORM;

  FrameImages(Device& device, VkExtent2D extent);

  VkExtent2D extent;
  Image hdr;
  Image depth;
  Image ldr;
  // Distinguishes successive FrameImages (handles may be reused after a resize); the overlay
  // keys its framebuffer on it.
  std::uint64_t generation;
};

}  // namespace penumbra::render
