#include "penumbra/render/upload_ring.h"

#include <algorithm>
#include <cstring>

namespace penumbra::render {

UploadRing::UploadRing(Device& device, VkDeviceSize initial_bytes) : device_(&device) {
  const auto& limits = device.properties().limits;
  min_alignment_ = std::max<VkDeviceSize>(
      {16, limits.minUniformBufferOffsetAlignment, limits.minStorageBufferOffsetAlignment});
  blocks_.push_back(create_buffer(device, std::max<VkDeviceSize>(initial_bytes, 4096), kUsage,
                                  /*host_visible=*/true));
}

Slice UploadRing::allocate(VkDeviceSize size, VkDeviceSize alignment) {
  const VkDeviceSize align = std::max(alignment, min_alignment_);
  const VkDeviceSize need = std::max<VkDeviceSize>(size, 1);
  VkDeviceSize offset = (head_ + align - 1) & ~(align - 1);
  if (offset + need > blocks_.back().size) {
    const VkDeviceSize grow = std::max(need, blocks_.back().size);
    blocks_.push_back(create_buffer(*device_, grow, kUsage, /*host_visible=*/true));
    offset = 0;
  }
  head_ = offset + need;
  used_total_ += need;
  Buffer& b = blocks_.back();
  return {b.get(), offset, size, static_cast<std::byte*>(b.mapped) + offset};
}

Slice UploadRing::upload(const void* bytes, VkDeviceSize size, VkDeviceSize alignment) {
  Slice s = allocate(size, alignment);
  if (size > 0) std::memcpy(s.data, bytes, size);
  return s;
}

void UploadRing::reset() {
  if (blocks_.size() > 1) {
    VkDeviceSize total = 0;
    for (const Buffer& b : blocks_) total += b.size;
    blocks_.clear();
    blocks_.push_back(create_buffer(*device_, total, kUsage, /*host_visible=*/true));
  }
  head_ = 0;
  used_total_ = 0;
}

VkDeviceSize UploadRing::capacity() const {
  VkDeviceSize total = 0;
  for (const Buffer& b : blocks_) total += b.size;
  return total;
}

}  // namespace penumbra::render

namespace penumbra::render {

void copy_to_buffer(VkCommandBuffer cmd, UploadRing& ring, const void* bytes, VkDeviceSize size,
                    VkBuffer dst, VkDeviceSize dst_offset) {
  if (size == 0) return;
  const Slice s = ring.upload(bytes, size);
  const VkBufferCopy region{s.offset, dst_offset, size};
  vkCmdCopyBuffer(cmd, s.buffer, dst, 1, &region);
}

void copy_to_image(VkCommandBuffer cmd, UploadRing& ring, const void* bytes, VkDeviceSize size,
                   const Image& dst, VkImageLayout old_layout) {
  const Slice s = ring.upload(bytes, size);
  barrier(cmd, {dst.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                old_layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL});
  VkBufferImageCopy region{};
  region.bufferOffset = s.offset;
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {dst.desc.extent.width, dst.desc.extent.height, 1};
  vkCmdCopyBufferToImage(cmd, s.buffer, dst.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                         &region);
  barrier(cmd, {dst.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
}

}  // namespace penumbra::render
