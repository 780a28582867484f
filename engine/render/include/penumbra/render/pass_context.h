// What a pass sees while the renderer records one frame.
//
// Every pass has two steps: prepare(ctx), recorded before any rendering scope (uploads and
// their barriers), and draw(ctx), recorded inside the renderer's dynamic-rendering scope for
// that pass (HDR colour + depth attached, viewport set).
//
// Threading: render thread only; the packet is read-only.
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>

#include "penumbra/render/packet.h"
#include "penumbra/render/resources.h"
#include "penumbra/render/upload_ring.h"

namespace penumbra::render {

// The environment shading's descriptors for the mesh pass (shadow_pass.h): binding 1, the
// EnvironmentBlock (shaders/mesh.glsl); binding 2, the shadow maps (unused slots repeat map 0).
struct EnvironmentBindings {
  VkDescriptorBufferInfo block{};
  VkDescriptorImageInfo maps[EnvironmentShading::kMaxSources]{};
};

struct FrameContext {
  Device& device;
  VkCommandBuffer cmd;
  UploadRing& ring;     // this frame's host-visible memory
  RetireList& retire;   // resources replaced this frame (destroyed once the GPU is done)
  std::uint64_t frame;  // number of the frame being recorded
  VkExtent2D extent;
  const RenderPacket& packet;
  VkDescriptorBufferInfo camera;  // the CameraBlock (shaders/common.glsl) for this frame
  glm::mat4 view_proj{1.0f};      // the camera's, for culling on the CPU
  float focal_px = 1.0f;          // pixels per unit of tan(angle) from the view axis
  // Set by the shadow pass before the scene passes draw; null: no environment shading.
  const EnvironmentBindings* environment = nullptr;
};

}  // namespace penumbra::render
