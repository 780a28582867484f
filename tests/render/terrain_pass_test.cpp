#include "penumbra/render/terrain_pass.h"

#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

// Level of detail at a 1-pixel budget looks like full detail: no cracks (the sky would show
// through), few pixels moved; and it draws far fewer triangles.
TEST(TerrainPass, LevelOfDetailMatchesFullDetailWithoutCracks) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(256, 144);
  RenderPacket p = test::terrain_scene();
  p.terrain.heights = test::make_hills(129, 0.25f);
  p.terrain.origin = {-16.0f, -16.0f, 0.0f};
  p.view.terrain_lod_pixels = 0.0f;
  const auto full = renderer.capture(p, target);
  const auto full_stats = renderer.stats();
  p.view.terrain_lod_pixels = 1.0f;
  const auto lod = renderer.capture(p, target);
  const auto lod_stats = renderer.stats();
  ASSERT_TRUE(full && lod);
  const ImageComparison c = compare_images(*lod, *full, 24);
  EXPECT_LT(c.fraction(), 0.01) << c.differing << " pixels differ";
  EXPECT_LT(lod_stats.terrain_triangles * 2, full_stats.terrain_triangles)
      << lod_stats.terrain_triangles << " vs " << full_stats.terrain_triangles;
  if (c.fraction() >= 0.01) {
    write_png(test::output_dir() + "/terrain_lod.png", *lod);
    write_png(test::output_dir() + "/terrain_lod.diff.png", c.diff);
  }
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

// A coarse budget (triangles of many sizes side by side) seen obliquely with the terrain filling
// the view and no sky: a crack between triangles shows the black clear colour. The hills are
// gentler than the view rays are steep, so a ray through a crack cannot meet the terrain again.
TEST(TerrainPass, NoCracksBetweenLevels) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(256, 144);
  RenderPacket p = test::terrain_scene();
  p.view.sky = false;
  p.terrain.albedo = glm::vec3(1.0f);
  auto hills = std::make_shared<data::HeightField>();
  hills->width = hills->height = 257;
  hills->cell_size = 0.5f;
  auto height = [](float x, float y) { return 2.0f * std::sin(0.1f * x) * std::cos(0.08f * y); };
  auto lighting = std::make_shared<std::vector<glm::vec3>>();
  for (int y = 0; y < 257; ++y) {
    for (int x = 0; x < 257; ++x) {
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      hills->heights.push_back(height(fx, fy));
      const glm::vec3 n = glm::normalize(glm::vec3(height(fx - 1, fy) - height(fx + 1, fy),
                                                   height(fx, fy - 1) - height(fx, fy + 1), 1.0f));
      lighting->push_back(glm::vec3(0.2f + 0.8f * std::max(n.x + n.z, 0.0f)));
    }
  }
  p.terrain.heights = hills;
  p.terrain.lighting = lighting;
  p.terrain.lighting_width = p.terrain.lighting_height = 257;
  p.terrain.origin = {-64.0f, -64.0f, 0.0f};
  p.camera.position = {0.0f, -10.0f, 25.0f};
  p.camera.target = {0.0f, 5.0f, 0.0f};
  p.camera.vertical_fov = 0.8f;
  p.view.terrain_lod_pixels = 12.0f;
  const auto image = renderer.capture(p, target);
  ASSERT_TRUE(image);
  std::size_t black = 0;
  for (std::size_t i = 0; i < image->pixels.size(); i += 4)
    black += image->pixels[i] + image->pixels[i + 1] + image->pixels[i + 2] == 0;
  EXPECT_EQ(black, 0u) << "cracks";
  EXPECT_GT(renderer.stats().terrain_triangles, 100u);
  EXPECT_LT(renderer.stats().terrain_triangles, 2u * 256 * 256 / 10) << "the budget coarsens";
  if (black > 0) write_png(test::output_dir() + "/terrain_cracks.png", *image);
}

TEST(TerrainPass, TerrainOutsideTheViewIsCulled) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(64, 36);
  RenderPacket p = test::terrain_scene();
  p.terrain.heights = test::make_hills(129, 1.0f);  // 128 m
  p.terrain.origin = {-64.0f, -64.0f, 0.0f};
  p.view.terrain_lod_pixels = 0.0f;  // full detail: 2 x 128 x 128 triangles in view
  p.camera.position = {-60.0f, -60.0f, 3.0f};
  p.camera.target = {-70.0f, -70.0f, 0.0f};  // looking out over the corner
  renderer.render(p, target);
  renderer.wait_idle();
  EXPECT_GE(renderer.stats().terrain_triangles, 1u);
  EXPECT_LT(renderer.stats().terrain_triangles, 2u * 128 * 128 / 10);
}

}  // namespace
}  // namespace penumbra::render
