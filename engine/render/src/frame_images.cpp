#include "penumbra/render/frame_images.h"

#include <atomic>

namespace penumbra::render {
namespace {
std::atomic<std::uint64_t> g_generation{0};
}

FrameImages::FrameImages(Device& device, VkExtent2D e)
    : extent(e),
      hdr(create_image(
          device, {e, kHdrFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                   VK_IMAGE_ASPECT_COLOR_BIT})),
      depth(create_image(device, {e, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                  VK_IMAGE_ASPECT_DEPTH_BIT})),
      ldr(create_image(
          device,
          {e, kLdrFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
           VK_IMAGE_ASPECT_COLOR_BIT})),
      generation(++g_generation) {}

}  // namespace penumbra::render
