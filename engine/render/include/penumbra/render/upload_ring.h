// UploadRing: per-frame host-visible memory for everything the CPU writes each frame (camera
// constants, vertex lighting, debug primitives, staging for uploads). One per frame in flight;
// reset() once that frame's fence has signalled, so nothing the GPU reads is overwritten.
//
// Allocation is linear. When a frame needs more than the current block, further blocks are
// added (earlier slices stay valid); the next reset() replaces them with one block of the
// total size, so after a warm-up the ring is one buffer that no longer changes.
//
// Threading: render thread only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/render/resources.h"

namespace penumbra::render {

struct Slice {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;
  void* data = nullptr;  // mapped, coherent
};

class UploadRing {
 public:
  static constexpr VkDeviceSize kUsage =
      VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT |
      VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

  UploadRing(Device& device, VkDeviceSize initial_bytes = 1 << 20);

  // `size` bytes aligned to `alignment` (a power of two; at least the device's uniform and
  // storage offset alignments are used for every slice).
  Slice allocate(VkDeviceSize size, VkDeviceSize alignment = 16);
  // Copies `bytes` into a new slice.
  Slice upload(const void* bytes, VkDeviceSize size, VkDeviceSize alignment = 16);
  void reset();

  VkDeviceSize capacity() const;
  VkDeviceSize used() const { return used_total_; }
  std::size_t blocks() const { return blocks_.size(); }

 private:
  Device* device_;
  VkDeviceSize min_alignment_;
  std::vector<Buffer> blocks_;
  VkDeviceSize head_ = 0;  // in the last block
  VkDeviceSize used_total_ = 0;
};

}  // namespace penumbra::render

namespace penumbra::render {

// Records a copy of `bytes` into the device-local `dst` at `dst_offset`, staged through the
// ring. The caller adds the barrier before the data is read.
void copy_to_buffer(VkCommandBuffer cmd, UploadRing& ring, const void* bytes, VkDeviceSize size,
                    VkBuffer dst, VkDeviceSize dst_offset = 0);
// Records the upload of a whole image (tightly packed texels), staged through the ring, from
// `old_layout` to SHADER_READ_ONLY_OPTIMAL; earlier fragment-shader reads of the image (the
// previous frame) complete before the copy writes it.
void copy_to_image(VkCommandBuffer cmd, UploadRing& ring, const void* bytes, VkDeviceSize size,
                   const Image& dst, VkImageLayout old_layout);

}  // namespace penumbra::render
