// The window path under a private Xvfb: open a window, render frames with the ImGui overlay,
// resize (the swapchain is recreated), take screenshots, close; validation on throughout.
#include "penumbra/render/window_target.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "penumbra/render/overlay.h"
#include "penumbra/render/renderer.h"
#include "penumbra/render/window.h"
#include "render_test_util.h"
#include "xvfb.h"

namespace penumbra::render {
namespace {

TEST(Window, OpenRenderResizeScreenshotClose) {
  test::Xvfb xvfb;
  std::printf("Xvfb on %s\n", xvfb.display().c_str());
  ASSERT_TRUE(Glfw::display_available());
  Glfw glfw;
  InstanceConfig config = test::validated_config();
  config.extensions = glfw.instance_extensions();
  Instance instance(config);
  {
    Window window(glfw, instance, 320, 180, "penumbra window test");
    DeviceConfig dc;
    dc.present_surface = window.surface();
    Device device(instance, dc);
    WindowTarget target(device, window);
    Renderer renderer(device);
    Overlay overlay(device, window);
    EXPECT_EQ(target.extent().width, 320u);
    EXPECT_EQ(target.extent().height, 180u);

    RenderPacket p = test::mesh_scene();
    OverlayStats stats;
    stats.device = device.name();
    stats.frame_ms = 16.0;
    stats.systems = {{"light", 2.5}, {"render_extract", 0.1}};
    ViewSettings view = p.view;
    for (int f = 0; f < 5; ++f) {
      window.poll_events();
      stats.passes = renderer.last_pass_times();
      overlay.build(stats, view);
      EXPECT_EQ(renderer.render(p, target, {false, &overlay}), FrameStatus::kRendered);
    }
    const auto plain = renderer.capture(p, target);
    overlay.build(stats, view);
    const auto with_overlay = renderer.capture(p, target, &overlay);
    ASSERT_TRUE(plain && with_overlay);
    EXPECT_EQ(plain->width, 320);
    EXPECT_EQ(plain->height, 180);
    const ImageComparison diff = compare_images(*with_overlay, *plain, 8);
    EXPECT_GT(diff.differing, 500u) << "the overlay draws over the frame";
    write_png(test::output_dir() + "/window_overlay.png", *with_overlay);

    // Resize: the framebuffer size changes after the X server configures the window; frames
    // keep rendering while the swapchain catches up.
    window.set_size(200, 120);
    const int before = target.swapchains_created();
    for (int i = 0; i < 200 && (target.extent().width != 200 || target.extent().height != 120);
         ++i) {
      window.poll_events();
      renderer.render(p, target);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_EQ(target.extent().width, 200u);
    EXPECT_EQ(target.extent().height, 120u);
    EXPECT_GT(target.swapchains_created(), before);
    const auto resized = renderer.capture(p, target);
    ASSERT_TRUE(resized);
    EXPECT_EQ(resized->width, 200);
    EXPECT_EQ(resized->height, 120);
    write_png(test::output_dir() + "/window_resized.png", *resized);

    EXPECT_FALSE(window.should_close());
    window.request_close();
    EXPECT_TRUE(window.should_close());
    renderer.wait_idle();
    EXPECT_EQ(renderer.stats().skipped, 0u);
  }
  EXPECT_EQ(instance.messages().total(), 0u) << instance.messages().summary();
}

}  // namespace
}  // namespace penumbra::render
