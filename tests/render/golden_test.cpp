// Golden images of the passes on lavapipe, 128x72 (tolerance: render_test_util.h).
#include <gtest/gtest.h>

#include <cstdlib>

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

// The goldens of shading pin the terrain's level of detail at 1 pixel, the budget they were
// made with (128x72 images of small terrains); the LOD itself is tested in terrain_pass_test.cpp.
TEST(Golden, TerrainWithLightingTexture) {
  RenderPacket p = test::terrain_scene();
  p.view.terrain_lod_pixels = 1.0f;
  check_scene(p, "terrain_lit");
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

// The environment rotation turns the map about z (packet.h: world radiance L(R_z(r) w) =
// map(w)): looking along d with the map turned by r shows what looking along R_z(-r) d shows
// with the map unturned. Compared image to image, with the golden tolerance.
TEST(Golden, EnvironmentRotationTurnsTheSkyAboutZ) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(kWidth, kHeight);
  RenderPacket turned = test::environment_scene();
  turned.sky.environment_rotation = 1.5707963f;  // quarter turn
  turned.camera.target = {0.0f, 1.0f, 0.3f};
  RenderPacket unturned = test::environment_scene();
  unturned.camera.target = {1.0f, 0.0f, 0.3f};  // R_z(-pi/2) (0, 1, 0.3)
  const auto a = renderer.capture(turned, target);
  const auto b = renderer.capture(unturned, target);
  ASSERT_TRUE(a && b);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a->pixels.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      if (std::abs(int(a->pixels[i + c]) - int(b->pixels[i + c])) > test::kGoldenTolerance) {
        ++differ;
        break;
      }
  EXPECT_LE(static_cast<double>(differ), test::kGoldenMaxFraction * kWidth * kHeight);
  // And the rotation matters: the unrotated view along d is a different picture.
  const auto c = renderer.capture(test::environment_scene(), target);
  ASSERT_TRUE(c);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < a->pixels.size(); i += 4)
    changed += std::abs(int(a->pixels[i]) - int(c->pixels[i])) > test::kGoldenTolerance;
  EXPECT_GT(changed, std::size_t{kWidth * kHeight / 10});
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

}  // namespace
}  // namespace penumbra::render
