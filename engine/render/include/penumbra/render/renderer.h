// Renderer: draws a RenderPacket into a Target, one frame per render() call.
//
// A frame, in command order (in a timed frame each scene pass has its own dynamic-rendering scope
// and a GPU timestamp mark follows each step, gpu_timer.h; an untimed frame draws the scene
// passes in one scope):
//   upload   terrain / mesh / environment uploads, this frame's vertex lighting, debug lists
//   shadows  one depth map per environment source (shadow_pass.h; only when the packet's
//            EnvironmentShading is enabled, valid and has sources and meshes, and the
//            sources or the meshes changed since the maps were drawn)
//   terrain  clears HDR colour + depth, draws the height field      } HDR image (RGBA16F)
//   meshes   per-vertex-lit meshes (or environment-shaded)          } + reversed depth
//   debug    wire spheres, lines, points                             }
//   sky      environment / procedural sky where nothing was drawn    }
//   tonemap  exposure + filmic -> LDR image (RGBA8, sRGB-encoded)
//   overlay  ImGui (when FrameRequest::overlay is set)
//   output   the target's copy (swapchain blit) and the optional readback for capture()
//
// Frames in flight: kFramesInFlight. Each has its command buffer, fence, upload ring, GPU timer
// and readback buffer; render() first waits for the fence of the frame that last used the same
// slot, so the CPU records frame N while the GPU may still run frame N-1. Resources replaced
// while in use are retired and destroyed once the frame that retired them has completed. A
// change of target size waits for the device to be idle and recreates the frame images.
//
// GPU pass times arrive kFramesInFlight frames late (when the slot's fence is next waited):
// last_pass_times() is the most recent completed frame, pass_table() accumulates them.
//
// Threading: one thread (the render thread) calls everything; the packet must not change during
// render(). With a WindowTarget that thread must be the main thread (GLFW).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/render/debug_pass.h"
#include "penumbra/render/frame_images.h"
#include "penumbra/render/gpu_timer.h"
#include "penumbra/render/image.h"
#include "penumbra/render/mesh_pass.h"
#include "penumbra/render/shadow_pass.h"
#include "penumbra/render/sky_pass.h"
#include "penumbra/render/target.h"
#include "penumbra/render/terrain_pass.h"
#include "penumbra/render/tonemap_pass.h"
#include "penumbra/render/upload_ring.h"

namespace penumbra::render {

class Overlay;

struct FrameRequest {
  bool capture = false;        // read this frame's LDR image back (see capture())
  Overlay* overlay = nullptr;  // draw the ImGui overlay built for this frame
};

enum class FrameStatus { kRendered, kSkipped };

class Renderer {
 public:
  static constexpr std::uint32_t kFramesInFlight = 2;

  struct Stats {
    std::uint64_t frames = 0;  // frames submitted
    std::uint64_t skipped = 0;
    std::size_t cached_meshes = 0;
    std::size_t rejected_meshes = 0;
    std::size_t retired = 0;         // resources waiting for the GPU before destruction
    VkDeviceSize ring_capacity = 0;  // all frames' upload rings
    VkDeviceSize uploaded = 0;       // ring bytes used by the last frame
    std::uint64_t terrain_triangles = 0, mesh_triangles = 0;  // drawn by the last frame
    std::size_t shadow_maps = 0;  // environment shadow maps the last frame used (0: shading off)
    std::uint64_t shadow_renders = 0;  // frames that re-rendered them (shadow_pass.h)
    // Why the last packet's EnvironmentShading was not drawn (check_environment_shading), "" if
    // it was (or was off); the frame is then drawn as without it.
    std::string environment_error;
  };

  explicit Renderer(Device& device);
  ~Renderer();  // waits for the device to be idle
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  FrameStatus render(const RenderPacket& packet, Target& target, const FrameRequest& request = {});
  // Renders one frame with readback and waits for it: the tonemapped image as shown (overlay
  // included). nullopt when the target skipped the frame.
  std::optional<ImageRgba8> capture(const RenderPacket& packet, Target& target,
                                    Overlay* overlay = nullptr);
  // Waits for every submitted frame (and collects their pass times).
  void wait_idle();

  // GPU pass times for one frame in `frames` (0: none; 1, the default: every frame). Timestamps
  // are not free on lavapipe: each mark flushes the llvmpipe scene, and a timed frame draws its
  // scene passes in separate rendering scopes (an untimed one in one scope), so a timed frame
  // takes about twice as long (docs/play.md). 0 still returns the frames already timed.
  void set_timing_interval(std::uint32_t frames) { timing_interval_ = frames; }
  const std::vector<PassTime>& last_pass_times() const { return last_pass_times_; }
  PassTimingTable& pass_table() { return table_; }
  Stats stats() const;
  Device& device() const { return *device_; }

 private:
  struct Frame {
    Unique<VkCommandPool> pool;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    Unique<VkFence> fence;
    std::unique_ptr<UploadRing> ring;
    std::unique_ptr<GpuTimer> timer;
    Buffer readback;
    bool submitted = false;
    bool capture = false;
    VkExtent2D capture_extent{0, 0};
    std::uint64_t number = 0;
  };
  void complete(Frame& f);  // waits for f's fence and collects its results
  void record_scene(FrameContext& ctx, Frame& f);
  void write_camera(FrameContext& ctx);

  Device* device_;
  SkyPass sky_;
  TerrainPass terrain_;
  MeshPass meshes_;
  ShadowPass shadows_;
  DebugPass debug_;
  TonemapPass tonemap_;
  std::array<Frame, kFramesInFlight> frames_;
  std::unique_ptr<FrameImages> images_;
  RetireList retire_;
  std::uint32_t slot_ = 0;
  std::uint64_t frame_number_ = 0;
  std::uint32_t timing_interval_ = 1;
  std::uint64_t completed_ = 0;  // every frame <= completed_ has finished on the GPU
  std::uint64_t skipped_ = 0;
  VkDeviceSize uploaded_ = 0;
  std::vector<PassTime> last_pass_times_;
  PassTimingTable table_;
  ImageRgba8 last_capture_;
  bool capture_ready_ = false;
};

}  // namespace penumbra::render
