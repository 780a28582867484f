// The valley game drawn: the committed session replayed through every system, the render extract
// and the renderer on lavapipe, against golden images at fixed frames (render_test_util.h: the
// render tests' tolerance). Frame 30: the round has just begun (daylight, the orb at the
// centre); 420: two beacons lit, the sky dimming; 780: most beacons lit at dusk.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "penumbra/game/valley_game.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "penumbra/systems/render_extract/render_extract.h"
#include "render_test_util.h"
#include "valley_replay.h"

namespace penumbra::game {
namespace {

TEST(ValleyGolden, TheRecordedSessionAtFixedFrames) {
  TerrainDemoConfig demo;
  demo.probes.cache_dir = PENUMBRA_TEST_OUTPUT_DIR "/valley_probes";
  demo.boulders.cache_dir = PENUMBRA_TEST_OUTPUT_DIR "/valley_spheres";
  test::ValleyReplay replay(2, demo);
  ecs::World& world = replay.world;

  render::test::TestContext ctx;
  render::Renderer renderer(ctx.device);
  render::OffscreenTarget target(192, 108);
  int frame = 0;
  for (const int shot : {30, 420, 780}) {
    for (; frame <= shot; ++frame) replay.step();
    const auto image = renderer.capture(world.resource<render::RenderPacket>(), target);
    ASSERT_TRUE(image.has_value());
    char name[32];
    std::snprintf(name, sizeof name, "valley_frame_%04d", shot);
    render::test::expect_matches_golden(*image, name);
  }
  EXPECT_GE(world.resource<const GameState>().beacons_lit, 3);
}

}  // namespace
}  // namespace penumbra::game
