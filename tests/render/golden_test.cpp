// Golden images of the passes on lavapipe, 128x72 (tolerance: render_test_util.h).
#include <gtest/gtest.h>

#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

constexpr std::uint32_t kWidth = 128, kHeight = 72;

void check_scene(const RenderPacket& packet, const std::string& name) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(kWidth, kHeight);
  const auto image = renderer.capture(packet, target);
  ASSERT_TRUE(image.has_value());
  EXPECT_EQ(image->width, static_cast<int>(kWidth));
  EXPECT_EQ(image->height, static_cast<int>(kHeight));
  test::expect_matches_golden(*image, name);
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

TEST(Golden, TerrainWithLightingTexture) {
  check_scene(test::terrain_scene(), "terrain_lit");
}

TEST(Golden, MeshesWithVertexColoursAndPreviewShading) {
  check_scene(test::mesh_scene(), "mesh_vertex_colors");
}

TEST(Golden, DebugSpheresLinesAndPoints) {
  check_scene(test::debug_scene(), "debug_primitives");
}

TEST(Golden, EnvironmentMapSky) {
  check_scene(test::environment_scene(), "sky_environment");
}

TEST(Golden, LightingOnlyViewAndLinearTonemap) {
  RenderPacket p = test::mesh_scene();
  p.view.lighting_only = true;
  p.view.tonemap = ViewSettings::Tonemap::kLinear;
  p.view.exposure_ev = -1.0f;
  check_scene(p, "mesh_lighting_only_linear");
}

}  // namespace
}  // namespace penumbra::render
