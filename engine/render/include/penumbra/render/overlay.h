// Overlay: a Dear ImGui (1.86) window over the frame in a WindowTarget: frame time, the CPU
// time of every system of the job graph with the work it did and skipped, the GPU time of every
// pass, and the debug-view toggles (ViewSettings: sky, terrain, meshes, debug primitives, lighting
// only, tonemap, exposure).
//
// ImGui draws into the LDR image after the tonemap (so screenshots of a windowed run show it),
// through ImGui's Vulkan backend, which needs a VkRenderPass: the overlay owns one (LDR format,
// load + store, COLOR_ATTACHMENT_OPTIMAL in and out) and a framebuffer per FrameImages.
// Input comes from ImGui's GLFW backend (callbacks installed on the window).
//
// Per frame: build() (host side: UI state, edits `view`), then Renderer::render with
// FrameRequest::overlay = this, which calls record(). One Overlay per process at a time (ImGui
// has one global context).
//
// Threading: main thread (GLFW input), the render thread being the main thread.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/render/frame_images.h"
#include "penumbra/render/gpu_timer.h"
#include "penumbra/render/packet.h"
#include "penumbra/render/window.h"

namespace penumbra::render {

// One system of the job graph in the panel: CPU ms and, when it reports them, the items it
// worked on and skipped as unchanged this frame (jobs::report_work).
struct OverlaySystem {
  std::string name;
  double ms = 0;
  bool reported = false;
  std::uint64_t done = 0, skipped = 0;
  // With `pausable`, the row has a checkbox: build() sets `paused` to what the user left it at
  // (the caller pauses or resumes the system: jobs::Schedule::set_paused).
  bool pausable = false, paused = false;
};

struct OverlayStats {
  std::string device;
  double frame_ms = 0;                 // wall time of the whole frame loop
  std::vector<OverlaySystem> systems;  // per system of the job graph
  std::vector<PassTime> passes;        // GPU ms per pass
  std::vector<std::string> lines;      // more lines (keys, switches)
  // A game's heads-up display: these lines in a small window at the top centre, shown whether
  // or not the panel is (empty: none). The panel (everything above) only when `panel` is set.
  std::vector<std::string> hud;
  bool panel = true;
};

class Overlay {
 public:
  // In a window: input and the display size from GLFW.
  Overlay(Device& device, Window& window);
  // Offscreen (a headless run's screenshots): no input, a display of `size` pixels, 1/30 s a
  // frame. One ImGui context per process: at most one Overlay at a time.
  Overlay(Device& device, VkExtent2D size);
  ~Overlay();
  Overlay(const Overlay&) = delete;
  Overlay& operator=(const Overlay&) = delete;

  // Builds this frame's UI; the view switches write `view`, the systems' checkboxes
  // stats.systems[i].paused.
  void build(OverlayStats& stats, ViewSettings& view);
  // Records the UI built by the last build() (nothing if none since the last record).
  void record(VkCommandBuffer cmd, const FrameImages& images);

 private:
  Device* device_;
  Unique<VkDescriptorPool> pool_;
  Unique<VkRenderPass> render_pass_;
  Unique<VkFramebuffer> framebuffer_;
  std::uint64_t framebuffer_generation_ = 0;
  bool built_ = false;
  bool glfw_ = false;
  VkExtent2D size_{0, 0};

  void init(Window* window);
};

}  // namespace penumbra::render
