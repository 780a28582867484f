// WindowTarget: presents frames to a Window through a swapchain.
//
// Each frame the renderer's LDR image is blitted to the acquired swapchain image (the blit
// converts RGBA/BGRA and scales while a resize is in flight), which is then presented. The
// swapchain is recreated (after the device is idle) when the framebuffer size changes, when
// acquire or present report VK_ERROR_OUT_OF_DATE_KHR or VK_SUBOPTIMAL_KHR; frames are skipped
// (acquire returns nullopt) while the window is minimised or has a zero-sized framebuffer.
//
// Format: an 8-bit UNORM format is preferred, because the LDR image already holds sRGB-encoded
// values; with only an _SRGB format available the blit would encode twice (too bright): a
// warning is printed.
//
// Threading: render thread, which must be the main thread (GLFW).
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/render/resources.h"
#include "penumbra/render/target.h"
#include "penumbra/render/window.h"

namespace penumbra::render {

class WindowTarget final : public Target {
 public:
  // slots: the renderer's frames in flight (one acquire semaphore each). vsync: FIFO present
  // mode; otherwise MAILBOX or IMMEDIATE where supported.
  WindowTarget(Device& device, Window& window, std::uint32_t slots = 2, bool vsync = true);
  ~WindowTarget() override;

  VkExtent2D extent() const override { return extent_; }
  std::optional<TargetFrame> acquire(std::uint32_t slot) override;
  void record_output(VkCommandBuffer cmd, VkImage ldr, VkExtent2D ldr_extent) override;
  void present() override;

  VkFormat format() const { return format_; }
  std::uint32_t image_count() const { return static_cast<std::uint32_t>(images_.size()); }
  // Swapchains created so far (1 after construction); tests check resizes recreate it.
  int swapchains_created() const { return created_; }

 private:
  void recreate();
  void destroy_swapchain();

  Device* device_;
  Window* window_;
  bool vsync_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<Unique<VkSemaphore>> acquired_;  // per slot
  std::vector<Unique<VkSemaphore>> rendered_;  // per swapchain image
  std::uint32_t image_index_ = 0;
  bool stale_ = false;  // recreate before the next acquire
  int created_ = 0;
};

}  // namespace penumbra::render
