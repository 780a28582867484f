#include "penumbra/render/window_target.h"

#include <algorithm>
#include <cstdio>

#include "penumbra/render/vk_check.h"

namespace penumbra::render {
namespace {
VkSurfaceFormatKHR choose_format(VkPhysicalDevice pd, VkSurfaceKHR surface) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(n);
  vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data());
  if (formats.empty()) throw std::runtime_error("the window surface reports no formats");
  for (VkFormat want : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM}) {
    for (const auto& f : formats)
      if (f.format == want && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
  }
  std::fprintf(stderr, "penumbra: no 8-bit UNORM swapchain format; colours will be off\n");
  return formats[0];
}

VkPresentModeKHR choose_present_mode(VkPhysicalDevice pd, VkSurfaceKHR surface, bool vsync) {
  if (vsync) return VK_PRESENT_MODE_FIFO_KHR;  // always supported
  std::uint32_t n = 0;
  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr);
  std::vector<VkPresentModeKHR> modes(n);
  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data());
  for (VkPresentModeKHR want : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
    if (std::find(modes.begin(), modes.end(), want) != modes.end()) return want;
  return VK_PRESENT_MODE_FIFO_KHR;
}
}  // namespace

WindowTarget::WindowTarget(Device& device, Window& window, std::uint32_t slots, bool vsync)
    : device_(&device), window_(&window), vsync_(vsync) {
  for (std::uint32_t i = 0; i < slots; ++i) acquired_.push_back(create_semaphore(device));
  recreate();
}

WindowTarget::~WindowTarget() {
  vkDeviceWaitIdle(device_->handle());
  destroy_swapchain();
}

void WindowTarget::destroy_swapchain() {
  rendered_.clear();
  images_.clear();
  if (swapchain_ != VK_NULL_HANDLE) {
    vkDestroySwapchainKHR(device_->handle(), swapchain_, nullptr);
    device_->count(ObjectKind::kSwapchain, -1);
    swapchain_ = VK_NULL_HANDLE;
  }
}

void WindowTarget::recreate() {
  const VkExtent2D fb = window_->framebuffer_extent();
  if (fb.width == 0 || fb.height == 0) return;  // minimised: keep the old one until restored
  vk_check(vkDeviceWaitIdle(device_->handle()), "vkDeviceWaitIdle");
  VkPhysicalDevice pd = device_->physical();
  VkSurfaceKHR surface = window_->surface();
  VkSurfaceCapabilitiesKHR caps;
  vk_check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface, &caps),
           "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
    throw std::runtime_error("the window surface does not allow transfers to its images");
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == 0xFFFFFFFFu) {
    extent.width = std::clamp(fb.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height = std::clamp(fb.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  if (extent.width == 0 || extent.height == 0) return;
  const VkSurfaceFormatKHR format = choose_format(pd, surface);
  std::uint32_t count = std::max(caps.minImageCount + 1, 2u);
  if (caps.maxImageCount > 0) count = std::min(count, caps.maxImageCount);

  VkSwapchainCreateInfoKHR info =
      vk_struct<VkSwapchainCreateInfoKHR>(VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR);
  info.surface = surface;
  info.minImageCount = count;
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                            ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                            : static_cast<VkCompositeAlphaFlagBitsKHR>(
                                  caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
  info.presentMode = choose_present_mode(pd, surface, vsync_);
  info.clipped = VK_TRUE;
  info.oldSwapchain = swapchain_;
  VkSwapchainKHR fresh = VK_NULL_HANDLE;
  vk_check(vkCreateSwapchainKHR(device_->handle(), &info, nullptr, &fresh), "vkCreateSwapchainKHR");
  destroy_swapchain();
  swapchain_ = fresh;
  device_->count(ObjectKind::kSwapchain, +1);
  ++created_;
  format_ = format.format;
  extent_ = extent;
  std::uint32_t n = 0;
  vkGetSwapchainImagesKHR(device_->handle(), swapchain_, &n, nullptr);
  images_.resize(n);
  vkGetSwapchainImagesKHR(device_->handle(), swapchain_, &n, images_.data());
  for (std::uint32_t i = 0; i < n; ++i) rendered_.push_back(create_semaphore(*device_));
  stale_ = false;
}

std::optional<TargetFrame> WindowTarget::acquire(std::uint32_t slot) {
  const VkExtent2D fb = window_->framebuffer_extent();
  if (fb.width == 0 || fb.height == 0) return std::nullopt;
  if (stale_ || swapchain_ == VK_NULL_HANDLE || fb.width != extent_.width ||
      fb.height != extent_.height)
    recreate();
  if (swapchain_ == VK_NULL_HANDLE) return std::nullopt;
  VkSemaphore acquired = acquired_[slot % acquired_.size()].get();
  const VkResult r = vkAcquireNextImageKHR(device_->handle(), swapchain_, UINT64_MAX, acquired,
                                           VK_NULL_HANDLE, &image_index_);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) {
    stale_ = true;
    return std::nullopt;  // the semaphore was not signalled; recreated next frame
  }
  if (r == VK_SUBOPTIMAL_KHR) {
    stale_ = true;  // usable now, recreated after this frame
  } else {
    vk_check(r, "vkAcquireNextImageKHR");
  }
  return TargetFrame{acquired, rendered_[image_index_].get()};
}

void WindowTarget::record_output(VkCommandBuffer cmd, VkImage ldr, VkExtent2D ldr_extent) {
  VkImage image = images_[image_index_];
  // Chained to the acquire semaphore, which the submit waits on at the transfer stage.
  barrier(cmd,
          {image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE,
           VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
           VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL});
  VkImageBlit region{};
  region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.srcOffsets[1] = {static_cast<std::int32_t>(ldr_extent.width),
                          static_cast<std::int32_t>(ldr_extent.height), 1};
  region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.dstOffsets[1] = {static_cast<std::int32_t>(extent_.width),
                          static_cast<std::int32_t>(extent_.height), 1};
  const bool same = ldr_extent.width == extent_.width && ldr_extent.height == extent_.height;
  vkCmdBlitImage(cmd, ldr, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region,
                 same ? VK_FILTER_NEAREST : VK_FILTER_LINEAR);
  barrier(cmd, {image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR});
}

void WindowTarget::present() {
  VkSemaphore wait = rendered_[image_index_].get();
  VkPresentInfoKHR info = vk_struct<VkPresentInfoKHR>(VK_STRUCTURE_TYPE_PRESENT_INFO_KHR);
  info.waitSemaphoreCount = 1;
  info.pWaitSemaphores = &wait;
  info.swapchainCount = 1;
  info.pSwapchains = &swapchain_;
  info.pImageIndices = &image_index_;
  const VkResult r = vkQueuePresentKHR(device_->queue(), &info);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
    stale_ = true;
    return;
  }
  vk_check(r, "vkQueuePresentKHR");
}

}  // namespace penumbra::render
