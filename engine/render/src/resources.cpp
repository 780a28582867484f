#include "penumbra/render/resources.h"

#include <algorithm>

#include "penumbra/render/vk_check.h"

namespace penumbra::render {

namespace {
// Memory for `req`: host-visible and coherent (mapped uploads) or device-local.
Unique<VkDeviceMemory> allocate_memory(Device& device, const VkMemoryRequirements& req,
                                       bool host_visible) {
  VkMemoryAllocateInfo alloc =
      vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex =
      host_visible
          ? device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                       VK_MEMORY_PROPERTY_HOST_COHERENT_BIT)
          : device.memory_type(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  vk_check(vkAllocateMemory(device.handle(), &alloc, nullptr, &memory), "vkAllocateMemory");
  return Unique<VkDeviceMemory>(device, memory, vkFreeMemory, ObjectKind::kMemory);
}
}  // namespace

Buffer create_buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage,
                     bool host_visible) {
  Buffer b;
  b.size = size;
  VkBufferCreateInfo info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer handle = VK_NULL_HANDLE;
  vk_check(vkCreateBuffer(device.handle(), &info, nullptr, &handle), "vkCreateBuffer");
  b.buffer = Unique<VkBuffer>(device, handle, vkDestroyBuffer, ObjectKind::kBuffer);

  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device.handle(), handle, &req);
  b.memory = allocate_memory(device, req, host_visible);
  const VkDeviceMemory memory = b.memory.get();
  vk_check(vkBindBufferMemory(device.handle(), handle, memory, 0), "vkBindBufferMemory");
  if (host_visible)
    vk_check(vkMapMemory(device.handle(), memory, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
  return b;
}

Image create_image(Device& device, const ImageDesc& desc) {
  Image img;
  img.desc = desc;
  VkImageCreateInfo info = vk_struct<VkImageCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO);
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = desc.format;
  info.extent = {desc.extent.width, desc.extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = desc.usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage handle = VK_NULL_HANDLE;
  vk_check(vkCreateImage(device.handle(), &info, nullptr, &handle), "vkCreateImage");
  img.image = Unique<VkImage>(device, handle, vkDestroyImage, ObjectKind::kImage);

  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(device.handle(), handle, &req);
  img.memory = allocate_memory(device, req, /*host_visible=*/false);
  const VkDeviceMemory memory = img.memory.get();
  vk_check(vkBindImageMemory(device.handle(), handle, memory, 0), "vkBindImageMemory");

  VkImageViewCreateInfo view =
      vk_struct<VkImageViewCreateInfo>(VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO);
  view.image = handle;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = desc.format;
  view.subresourceRange = {desc.aspect, 0, 1, 0, 1};
  VkImageView v = VK_NULL_HANDLE;
  vk_check(vkCreateImageView(device.handle(), &view, nullptr, &v), "vkCreateImageView");
  img.view = Unique<VkImageView>(device, v, vkDestroyImageView, ObjectKind::kImageView);
  return img;
}

Unique<VkSemaphore> create_semaphore(Device& device) {
  VkSemaphoreCreateInfo info =
      vk_struct<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
  VkSemaphore s = VK_NULL_HANDLE;
  vk_check(vkCreateSemaphore(device.handle(), &info, nullptr, &s), "vkCreateSemaphore");
  return Unique<VkSemaphore>(device, s, vkDestroySemaphore, ObjectKind::kSemaphore);
}

Unique<VkFence> create_fence(Device& device, bool signalled) {
  VkFenceCreateInfo info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  if (signalled) info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  VkFence f = VK_NULL_HANDLE;
  vk_check(vkCreateFence(device.handle(), &info, nullptr, &f), "vkCreateFence");
  return Unique<VkFence>(device, f, vkDestroyFence, ObjectKind::kFence);
}

Unique<VkSampler> create_sampler(Device& device, VkFilter filter, VkSamplerAddressMode address) {
  VkSamplerCreateInfo info = vk_struct<VkSamplerCreateInfo>(VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO);
  info.magFilter = filter;
  info.minFilter = filter;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = info.addressModeV = info.addressModeW = address;
  info.maxLod = 0.0f;
  VkSampler s = VK_NULL_HANDLE;
  vk_check(vkCreateSampler(device.handle(), &info, nullptr, &s), "vkCreateSampler");
  return Unique<VkSampler>(device, s, vkDestroySampler, ObjectKind::kSampler);
}

void barrier(VkCommandBuffer cmd, const ImageBarrier& b) {
  VkImageMemoryBarrier2 ib =
      vk_struct<VkImageMemoryBarrier2>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2);
  ib.srcStageMask = b.src_stage;
  ib.srcAccessMask = b.src_access;
  ib.dstStageMask = b.dst_stage;
  ib.dstAccessMask = b.dst_access;
  ib.oldLayout = b.old_layout;
  ib.newLayout = b.new_layout;
  ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  ib.image = b.image;
  ib.subresourceRange = {b.aspect, 0, 1, 0, 1};
  VkDependencyInfo dep = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &ib;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  VkMemoryBarrier2 mb = vk_struct<VkMemoryBarrier2>(VK_STRUCTURE_TYPE_MEMORY_BARRIER_2);
  mb.srcStageMask = src_stage;
  mb.srcAccessMask = src_access;
  mb.dstStageMask = dst_stage;
  mb.dstAccessMask = dst_access;
  VkDependencyInfo dep = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &mb;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void RetireList::retire(std::uint64_t frame, Buffer buffer) {
  buffers_.emplace_back(frame, std::move(buffer));
}
void RetireList::retire(std::uint64_t frame, Image image) {
  images_.emplace_back(frame, std::move(image));
}

void RetireList::collect(std::uint64_t completed_frame) {
  auto done = [&](const auto& e) { return e.first <= completed_frame; };
  buffers_.erase(std::remove_if(buffers_.begin(), buffers_.end(), done), buffers_.end());
  images_.erase(std::remove_if(images_.begin(), images_.end(), done), images_.end());
}

void RetireList::clear() {
  buffers_.clear();
  images_.clear();
}

}  // namespace penumbra::render
