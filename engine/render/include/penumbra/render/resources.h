// RAII wrappers for the Vulkan objects the renderer owns, each counted in Device's object
// counts while alive, plus buffers, images, barriers and deferred release.
//
// Memory: one VkDeviceMemory per buffer or image. The renderer owns few, long-lived resources
// (frame images, terrain, one buffer per cached mesh, one upload ring per frame in flight), so
// a sub-allocator would not pay for itself; the object counts show the allocation count.
//
// Threading: wrappers are owned and destroyed by the render thread.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "penumbra/render/device.h"

namespace penumbra::render {

// An owned VkDevice child object: destroyed with `destroy` (vkDestroyX or vkFreeMemory).
template <class H>
class Unique {
 public:
  using Destroy = void (*)(VkDevice, H, const VkAllocationCallbacks*);

  Unique() = default;
  Unique(Device& device, H handle, Destroy destroy, ObjectKind kind)
      : device_(&device), handle_(handle), destroy_(destroy), kind_(kind) {
    if (handle_ != VK_NULL_HANDLE) device_->count(kind_, +1);
  }
  ~Unique() { reset(); }
  Unique(Unique&& o) noexcept { *this = std::move(o); }
  Unique& operator=(Unique&& o) noexcept {
    if (this != &o) {
      reset();
      device_ = o.device_;
      handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
      destroy_ = o.destroy_;
      kind_ = o.kind_;
    }
    return *this;
  }
  Unique(const Unique&) = delete;
  Unique& operator=(const Unique&) = delete;

  H get() const { return handle_; }
  explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }
  void reset() {
    if (handle_ == VK_NULL_HANDLE) return;
    destroy_(device_->handle(), handle_, nullptr);
    device_->count(kind_, -1);
    handle_ = VK_NULL_HANDLE;
  }

 private:
  Device* device_ = nullptr;
  H handle_ = VK_NULL_HANDLE;
  Destroy destroy_ = nullptr;
  ObjectKind kind_ = ObjectKind::kBuffer;
};

struct Buffer {
  Unique<VkBuffer> buffer;
  Unique<VkDeviceMemory> memory;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  // host-visible buffers stay mapped for their lifetime
  VkBuffer get() const { return buffer.get(); }
};

// host_visible: HOST_VISIBLE | HOST_COHERENT, mapped (upload rings, readback); otherwise
// DEVICE_LOCAL (filled by transfers).
Buffer create_buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage,
                     bool host_visible);

struct ImageDesc {
  VkExtent2D extent{1, 1};
  VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
  VkImageUsageFlags usage = 0;
  VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
};

struct Image {
  Unique<VkImage> image;
  Unique<VkDeviceMemory> memory;
  Unique<VkImageView> view;
  ImageDesc desc;
  VkImage get() const { return image.get(); }
};

Image create_image(Device& device, const ImageDesc& desc);

Unique<VkSemaphore> create_semaphore(Device& device);
Unique<VkFence> create_fence(Device& device, bool signalled);
Unique<VkSampler> create_sampler(Device& device, VkFilter filter, VkSamplerAddressMode address);

// One image layout transition / memory dependency (synchronization2).
struct ImageBarrier {
  VkImage image = VK_NULL_HANDLE;
  VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
  VkPipelineStageFlags2 src_stage = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 src_access = VK_ACCESS_2_NONE;
  VkPipelineStageFlags2 dst_stage = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 dst_access = VK_ACCESS_2_NONE;
  VkImageLayout old_layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImageLayout new_layout = VK_IMAGE_LAYOUT_UNDEFINED;
};
void barrier(VkCommandBuffer cmd, const ImageBarrier& b);
// A global memory dependency (e.g. transfer writes -> vertex/index/shader reads).
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

// Resources the GPU may still use: destroyed once the frame that retired them has completed.
class RetireList {
 public:
  void retire(std::uint64_t frame, Buffer buffer);
  void retire(std::uint64_t frame, Image image);
  // Destroys everything retired at frames <= completed_frame.
  void collect(std::uint64_t completed_frame);
  void clear();  // after Device::wait_idle()
  std::size_t size() const { return buffers_.size() + images_.size(); }

 private:
  std::vector<std::pair<std::uint64_t, Buffer>> buffers_;
  std::vector<std::pair<std::uint64_t, Image>> images_;
};

}  // namespace penumbra::render
