// The overlay offscreen (a headless run's screenshots): the HUD's lines are drawn at the top
// centre of the captured image, and nothing else of it changes; the panel stays off.
#include "penumbra/render/overlay.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

TEST(Overlay, OffscreenHudDrawsAtTheTopCentreOnly) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(320, 180);
  RenderPacket packet;  // clear + tonemap: a flat image
  const auto plain = renderer.capture(packet, target);
  Overlay overlay(ctx.device, VkExtent2D{320, 180});
  OverlayStats stats;
  stats.panel = false;
  stats.hud = {"beacons 3 / 7   score 635"};
  ViewSettings view = packet.view;
  overlay.build(stats, view);
  overlay.build(stats, view);  // ImGui sizes the auto-resized window from its last frame
  const auto with_hud = renderer.capture(packet, target, &overlay);
  ASSERT_TRUE(plain && with_hud);
  int inside = 0, outside = 0;
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) {
      const std::size_t i = 4 * (static_cast<std::size_t>(y) * 320 + x);
      int d = 0;
      for (int c = 0; c < 3; ++c) d += std::abs(plain->pixels[i + c] - with_hud->pixels[i + c]);
      if (d == 0) continue;
      (y < 40 && x > 40 && x < 280 ? inside : outside) += 1;
    }
  EXPECT_GT(inside, 200) << "the HUD's text and box";
  EXPECT_EQ(outside, 0) << "no panel, nothing below the HUD";
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

}  // namespace
}  // namespace penumbra::render
