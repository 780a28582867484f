#include "penumbra/render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "penumbra/render/camera.h"
#include "penumbra/render/overlay.h"
#include "penumbra/render/vk_check.h"

namespace penumbra::render {
namespace {
// Mirrors CameraBlock in shaders/common.glsl (std140).
struct CameraBlock {
  glm::mat4 view_proj;
  glm::mat4 inv_view_proj;
  glm::vec4 position, sun_direction, sun_radiance, zenith, horizon, ground, params;
};
static_assert(sizeof(CameraBlock) == 240);

// Begins a rendering scope on the HDR colour + depth images; `clear` on the first one.
void begin_hdr(VkCommandBuffer cmd, const FrameImages& images, bool clear) {
  VkRenderingAttachmentInfo color =
      vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
  color.imageView = images.hdr.view.get();
  color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  color.clearValue.color = {{0.0f, 0.0f, 0.0f, 1.0f}};
  VkRenderingAttachmentInfo depth =
      vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
  depth.imageView = images.depth.view.get();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  depth.clearValue.depthStencil = {0.0f, 0};  // reversed depth: 0 is the far plane
  VkRenderingInfo info = vk_struct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
  info.renderArea = {{0, 0}, images.extent};
  info.layerCount = 1;
  info.colorAttachmentCount = 1;
  info.pColorAttachments = &color;
  info.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &info);
  set_viewport(cmd, images.extent);
}
}  // namespace

Renderer::Renderer(Device& device)
    : device_(&device),
      sky_(device, FrameImages::kHdrFormat, FrameImages::kDepthFormat),
      terrain_(device, FrameImages::kHdrFormat, FrameImages::kDepthFormat),
      meshes_(device, FrameImages::kHdrFormat, FrameImages::kDepthFormat),
      shadows_(device),
      debug_(device, FrameImages::kHdrFormat, FrameImages::kDepthFormat),
      tonemap_(device, FrameImages::kLdrFormat) {
  for (Frame& f : frames_) {
    VkCommandPoolCreateInfo pool =
        vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    pool.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    pool.queueFamilyIndex = device.queue_family();
    VkCommandPool p = VK_NULL_HANDLE;
    vk_check(vkCreateCommandPool(device.handle(), &pool, nullptr, &p), "vkCreateCommandPool");
    f.pool = Unique<VkCommandPool>(device, p, vkDestroyCommandPool, ObjectKind::kCommandPool);
    VkCommandBufferAllocateInfo alloc =
        vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    alloc.commandPool = p;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    vk_check(vkAllocateCommandBuffers(device.handle(), &alloc, &f.cmd), "vkAllocateCommandBuffers");
    f.fence = create_fence(device, /*signalled=*/true);
    f.ring = std::make_unique<UploadRing>(device);
    f.timer = std::make_unique<GpuTimer>(device);
  }
}

Renderer::~Renderer() {
  vkDeviceWaitIdle(device_->handle());
}

void Renderer::complete(Frame& f) {
  if (!f.submitted) return;
  VkFence fence = f.fence.get();
  vk_check(vkWaitForFences(device_->handle(), 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  f.submitted = false;
  completed_ = std::max(completed_, f.number);
  std::vector<PassTime> times = f.timer->read();
  if (!times.empty()) {
    table_.add(times);
    last_pass_times_ = std::move(times);
  }
  if (f.capture) {
    f.capture = false;
    last_capture_.width = static_cast<int>(f.capture_extent.width);
    last_capture_.height = static_cast<int>(f.capture_extent.height);
    const std::size_t bytes =
        static_cast<std::size_t>(last_capture_.width) * last_capture_.height * 4;
    const auto* src = static_cast<const std::uint8_t*>(f.readback.mapped);
    last_capture_.pixels.assign(src, src + bytes);
    capture_ready_ = true;
  }
}

void Renderer::write_camera(FrameContext& ctx) {
  const RenderPacket& p = ctx.packet;
  CameraBlock c;
  c.view_proj = ctx.view_proj;
  c.inv_view_proj = glm::inverse(c.view_proj);
  c.position = glm::vec4(p.camera.position, 1.0f);
  const float len = glm::length(p.sky.sun_direction);
  c.sun_direction = glm::vec4(len > 0 ? p.sky.sun_direction / len : glm::vec3(0, 0, 1), 0.0f);
  c.sun_radiance = glm::vec4(p.sky.sun_radiance, 0.0f);
  c.zenith = glm::vec4(p.sky.zenith, 0.0f);
  c.horizon = glm::vec4(p.sky.horizon, 0.0f);
  c.ground = glm::vec4(p.sky.ground, 0.0f);
  float point_size = std::max(1.0f, p.view.point_size);
  point_size = device_->large_points()
                   ? std::min(point_size, device_->properties().limits.pointSizeRange[1])
                   : 1.0f;
  c.params = glm::vec4(p.view.lighting_only ? 1.0f : 0.0f, point_size, p.sky.environment_intensity,
                       p.sky.environment_rotation);
  const Slice s = ctx.ring.upload(&c, sizeof c);
  ctx.camera = {s.buffer, s.offset, sizeof c};
}

void Renderer::record_scene(FrameContext& ctx, Frame& f) {
  const ViewSettings& view = ctx.packet.view;
  const VkCommandBuffer cmd = ctx.cmd;
  sky_.prepare(ctx);
  terrain_.prepare(ctx);
  meshes_.prepare(ctx);
  shadows_.prepare(ctx, meshes_);
  debug_.prepare(ctx);
  write_camera(ctx);
  f.timer->mark(cmd, "upload");
  if (shadows_.stale()) {
    shadows_.record(ctx, meshes_);
    f.timer->mark(cmd, "shadows");
  }
  ctx.environment = shadows_.bindings();

  // The previous frame's tonemap read of HDR and its depth tests finish before this frame
  // writes them; old contents are discarded.
  barrier(cmd,
          {images_->hdr.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
           VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
           VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT,
           VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
  const VkPipelineStageFlags2 tests =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  barrier(cmd, {images_->depth.get(), VK_IMAGE_ASPECT_DEPTH_BIT, tests,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, tests,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL});

  struct Scope {
    const char* name;
    bool enabled;
    void (*draw)(Renderer&, FrameContext&);
  };
  const Scope scopes[] = {
      {"terrain", view.terrain, [](Renderer& r, FrameContext& c) { r.terrain_.draw(c); }},
      {"meshes", view.meshes, [](Renderer& r, FrameContext& c) { r.meshes_.draw(c); }},
      {"debug", view.debug, [](Renderer& r, FrameContext& c) { r.debug_.draw(c); }},
      {"sky", view.sky, [](Renderer& r, FrameContext& c) { r.sky_.draw(c); }},
  };
  if (!f.timer->enabled()) {
    // Untimed: one rendering scope for every scene pass (on lavapipe each scope end is a flush
    // of the llvmpipe scene; docs/play.md measures what the timed frames' flushes cost).
    begin_hdr(cmd, *images_, /*clear=*/true);
    for (const Scope& s : scopes)
      if (s.enabled) s.draw(*this, ctx);
    vkCmdEndRendering(cmd);
    return;
  }
  bool first = true;
  for (const Scope& s : scopes) {
    if (!s.enabled && !first) continue;
    begin_hdr(cmd, *images_, first);
    if (s.enabled) s.draw(*this, ctx);
    vkCmdEndRendering(cmd);
    f.timer->mark(cmd, s.name);
    first = false;
  }
}

FrameStatus Renderer::render(const RenderPacket& packet, Target& target,
                             const FrameRequest& request) {
  Frame& f = frames_[slot_];
  complete(f);
  retire_.collect(completed_);
  const std::optional<TargetFrame> out = target.acquire(slot_);
  const VkExtent2D extent = target.extent();
  if (!out || extent.width == 0 || extent.height == 0) {
    ++skipped_;
    return FrameStatus::kSkipped;
  }
  if (!images_ || images_->extent.width != extent.width ||
      images_->extent.height != extent.height) {
    wait_idle();
    retire_.clear();
    images_ = std::make_unique<FrameImages>(*device_, extent);
  }

  VkFence fence = f.fence.get();
  vk_check(vkResetFences(device_->handle(), 1, &fence), "vkResetFences");
  vk_check(vkResetCommandPool(device_->handle(), f.pool.get(), 0), "vkResetCommandPool");
  f.ring->reset();
  f.number = ++frame_number_;
  VkCommandBufferBeginInfo begin =
      vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk_check(vkBeginCommandBuffer(f.cmd, &begin), "vkBeginCommandBuffer");
  const VkCommandBuffer cmd = f.cmd;
  f.timer->start(cmd, timing_interval_ > 0 && f.number % timing_interval_ == 0);

  FrameContext ctx{*device_, cmd, *f.ring, retire_, f.number, extent, packet, {}};
  const float aspect = static_cast<float>(extent.width) / static_cast<float>(extent.height);
  ctx.view_proj = view_projection(packet.camera, aspect);
  ctx.focal_px =
      0.5f * static_cast<float>(extent.height) / std::tan(0.5f * packet.camera.vertical_fov);
  record_scene(ctx, f);

  barrier(cmd,
          {images_->hdr.get(), VK_IMAGE_ASPECT_COLOR_BIT,
           VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
           VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
           VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  // The previous frame's copy out of LDR finishes before the tonemap overwrites it.
  barrier(cmd, {images_->ldr.get(), VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT,
                VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
  VkRenderingAttachmentInfo ldr =
      vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
  ldr.imageView = images_->ldr.view.get();
  ldr.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  ldr.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  ldr.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  VkRenderingInfo info = vk_struct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
  info.renderArea = {{0, 0}, extent};
  info.layerCount = 1;
  info.colorAttachmentCount = 1;
  info.pColorAttachments = &ldr;
  vkCmdBeginRendering(cmd, &info);
  set_viewport(cmd, extent);
  tonemap_.draw(cmd, images_->hdr, packet.view);
  vkCmdEndRendering(cmd);
  f.timer->mark(cmd, "tonemap");
  if (request.overlay != nullptr) {
    request.overlay->record(cmd, *images_);
    f.timer->mark(cmd, "overlay");
  }

  barrier(cmd,
          {images_->ldr.get(), VK_IMAGE_ASPECT_COLOR_BIT,
           VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
           VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
           VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL});
  target.record_output(cmd, images_->ldr.get(), extent);
  if (request.capture) {
    const VkDeviceSize bytes = VkDeviceSize{extent.width} * extent.height * 4;
    if (f.readback.size < bytes)
      f.readback = create_buffer(*device_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent.width, extent.height, 1};
    vkCmdCopyImageToBuffer(cmd, images_->ldr.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           f.readback.get(), 1, &region);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
    f.capture = true;
    f.capture_extent = extent;
  }
  f.timer->mark(cmd, "output");
  vk_check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

  VkCommandBufferSubmitInfo cmd_info =
      vk_struct<VkCommandBufferSubmitInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO);
  cmd_info.commandBuffer = cmd;
  VkSemaphoreSubmitInfo wait =
      vk_struct<VkSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO);
  wait.semaphore = out->wait;
  wait.stageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;  // only the output copy waits
  VkSemaphoreSubmitInfo signal =
      vk_struct<VkSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO);
  signal.semaphore = out->signal;
  signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  VkSubmitInfo2 submit = vk_struct<VkSubmitInfo2>(VK_STRUCTURE_TYPE_SUBMIT_INFO_2);
  submit.waitSemaphoreInfoCount = out->wait ? 1 : 0;
  submit.pWaitSemaphoreInfos = &wait;
  submit.signalSemaphoreInfoCount = out->signal ? 1 : 0;
  submit.pSignalSemaphoreInfos = &signal;
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cmd_info;
  vk_check(vkQueueSubmit2(device_->queue(), 1, &submit, fence), "vkQueueSubmit2");
  f.submitted = true;
  uploaded_ = f.ring->used();
  target.present();
  slot_ = (slot_ + 1) % kFramesInFlight;
  return FrameStatus::kRendered;
}

std::optional<ImageRgba8> Renderer::capture(const RenderPacket& packet, Target& target,
                                            Overlay* overlay) {
  capture_ready_ = false;
  if (render(packet, target, {true, overlay}) != FrameStatus::kRendered) return std::nullopt;
  wait_idle();
  if (!capture_ready_) return std::nullopt;
  capture_ready_ = false;
  return std::move(last_capture_);
}

void Renderer::wait_idle() {
  // Oldest first, so pass times arrive in frame order.
  for (std::uint32_t i = 0; i < kFramesInFlight; ++i)
    complete(frames_[(slot_ + i) % kFramesInFlight]);
  retire_.collect(completed_);
}

Renderer::Stats Renderer::stats() const {
  Stats s;
  s.frames = frame_number_;
  s.skipped = skipped_;
  s.cached_meshes = meshes_.cached_meshes();
  s.rejected_meshes = meshes_.rejected();
  s.retired = retire_.size();
  for (const Frame& f : frames_) s.ring_capacity += f.ring->capacity();
  s.uploaded = uploaded_;
  s.terrain_triangles = terrain_.triangles();
  s.mesh_triangles = meshes_.triangles();
  s.shadow_maps = shadows_.maps();
  s.shadow_renders = shadows_.renders();
  s.environment_error = shadows_.error();
  return s;
}

}  // namespace penumbra::render
