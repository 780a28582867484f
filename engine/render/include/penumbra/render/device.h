// Device: the chosen physical device, the logical device and its one graphics(+present) queue.
//
// Requirements (a device lacking one is unsuitable, see device_select.h): Vulkan 1.3 with the
// dynamicRendering and synchronization2 features, VK_KHR_push_descriptor (every pass binds its
// few descriptors with vkCmdPushDescriptorSetKHR: no pools or per-frame sets to manage), a
// graphics queue, and, when a surface is given, present support and VK_KHR_swapchain.
// largePoints is enabled where available (debug points larger than one pixel).
//
// Object counts: the RAII wrappers of resources.h count every live Vulkan object they own per
// kind, so tests can check that nothing grows frame after frame.
//
// Threading: the queue is used by the render thread only (submit_and_wait included); the
// counters are atomic.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "penumbra/render/device_select.h"
#include "penumbra/render/instance.h"

namespace penumbra::render {

enum class ObjectKind : int {
  kBuffer,
  kImage,
  kImageView,
  kMemory,
  kSampler,
  kPipeline,
  kPipelineLayout,
  kSetLayout,
  kShaderModule,
  kSemaphore,
  kFence,
  kCommandPool,
  kQueryPool,
  kDescriptorPool,
  kRenderPass,
  kFramebuffer,
  kSwapchain,
  kCount
};
const char* object_kind_name(ObjectKind kind);

struct ObjectCounts {
  std::array<std::int64_t, static_cast<int>(ObjectKind::kCount)> live{};
  std::int64_t total() const;
  bool operator==(const ObjectCounts&) const = default;
  std::string text() const;  // "buffer 12, image 3, ..." (non-zero kinds)
};

struct DeviceConfig {
  std::string force;                              // device_select.h; "" = $PENUMBRA_DEVICE / auto
  VkSurfaceKHR present_surface = VK_NULL_HANDLE;  // window targets: must present to it
};

class Device {
 public:
  // Throws std::runtime_error (listing the devices) when no suitable device is found.
  Device(Instance& instance, const DeviceConfig& config = {});
  ~Device();  // waits for the device to be idle
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  Instance& instance() const { return *instance_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice handle() const { return device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  std::string name() const { return properties_.deviceName; }
  bool large_points() const { return large_points_; }
  bool timestamps() const { return timestamps_; }
  const std::vector<DeviceCandidate>& candidates() const { return candidates_; }
  // vkCmdPushDescriptorSetKHR, resolved for this device.
  PFN_vkCmdPushDescriptorSetKHR push_descriptor_fn() const { return push_descriptor_; }

  // A memory type index allowed by `type_bits` with all `required` flags, preferring one that
  // also has `preferred`. Throws when none exists.
  std::uint32_t memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred = 0) const;

  // Records `record` into a one-time command buffer, submits it and waits (set-up uploads).
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record);
  void wait_idle() const;

  void count(ObjectKind kind, int delta) {
    live_[static_cast<int>(kind)].fetch_add(delta, std::memory_order_relaxed);
  }
  ObjectCounts object_counts() const;

 private:
  Instance* instance_;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  bool large_points_ = false;
  bool timestamps_ = false;
  std::vector<DeviceCandidate> candidates_;
  VkCommandPool upload_pool_ = VK_NULL_HANDLE;
  PFN_vkCmdPushDescriptorSetKHR push_descriptor_ = nullptr;
  std::array<std::atomic<std::int64_t>, static_cast<int>(ObjectKind::kCount)> live_{};
};

}  // namespace penumbra::render
