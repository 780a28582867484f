// Target: where a finished frame goes. The renderer draws every frame into its FrameImages
// (frame_images.h) and then hands the LDR image to the target: the offscreen target keeps it
// (screenshots read it back), the window target copies it to a swapchain image and presents.
//
// Per frame the renderer calls, on the render thread:
//   extent()                    the size to render at
//   acquire(slot)               nullopt: skip this frame (minimised, swapchain just recreated)
//   record_output(cmd, ldr)     the LDR image is in TRANSFER_SRC_OPTIMAL
//   (submit: waits on TargetFrame::wait, signals TargetFrame::signal)
//   present()
// `slot` (0 .. frames in flight - 1) identifies the frame-in-flight whose fence the renderer
// has waited for, so per-slot objects of the target (acquire semaphores) are free to reuse.
#pragma once

#include <cstdint>
#include <optional>

#include <vulkan/vulkan.h>

namespace penumbra::render {

struct TargetFrame {
  VkSemaphore wait = VK_NULL_HANDLE;    // the submit waits on it (image acquired)
  VkSemaphore signal = VK_NULL_HANDLE;  // the submit signals it (present waits on it)
};

class Target {
 public:
  virtual ~Target() = default;
  virtual VkExtent2D extent() const = 0;
  virtual std::optional<TargetFrame> acquire(std::uint32_t slot) = 0;
  virtual void record_output(VkCommandBuffer cmd, VkImage ldr, VkExtent2D ldr_extent) = 0;
  virtual void present() = 0;
};

}  // namespace penumbra::render
