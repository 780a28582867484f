#include "penumbra/render/terrain_pass.h"

#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

TEST(TerrainPass, SelectsTheCoarsestLevelWithinThePixelBudget) {
  const float error[TerrainPass::kLods] = {0.0f, 0.01f, 0.05f, 0.2f, 1.0f, 4.0f};
  const float focal = 500.0f;  // pixels per unit tangent
  // 1 px at 100 m allows 0.2 m of error: level 3.
  EXPECT_EQ(TerrainPass::select_level(error, 100.0f, focal, 1.0f), 3);
  EXPECT_EQ(TerrainPass::select_level(error, 1000.0f, focal, 1.0f), 4);
  EXPECT_EQ(TerrainPass::select_level(error, 10000.0f, focal, 1.0f), 5);
  EXPECT_EQ(TerrainPass::select_level(error, 1.0f, focal, 1.0f), 0);
  EXPECT_EQ(TerrainPass::select_level(error, 0.0f, focal, 1.0f), 0) << "camera inside the chunk";
  EXPECT_EQ(TerrainPass::select_level(error, 10000.0f, focal, 0.0f), 0) << "LOD off";
}

// The distance select_level divides by: a vertical error seen from straight above moves little on
// screen; seen level with the chunk, as much as at its nearest distance.
TEST(TerrainPass, VerticalErrorShowsLessFromAbove) {
  const glm::vec3 lo(-1.0f, -1.0f, 0.0f), hi(1.0f, 1.0f, 2.0f);
  const float above = TerrainPass::vertical_error_distance({0, 0, 100}, lo, hi);
  EXPECT_NEAR(above, (2.0f + 98.0f * 98.0f) / std::sqrt(2.0f), 1e-2f) << "h^2 + z^2 over h, corner";
  EXPECT_NEAR(TerrainPass::vertical_error_distance({10, 0, 1}, lo, hi), 9.0f, 1e-5f) << "level";
  EXPECT_EQ(TerrainPass::vertical_error_distance({0, 0, 1}, lo, hi), 0.0f) << "inside";
  // At 45 degrees down (h = z) the factor h / (h^2 + z^2) = 1 / (2 h) is the largest for that z.
  EXPECT_NEAR(TerrainPass::vertical_error_distance({11, 0, 12}, lo, hi), 20.0f, 1e-4f);
  // Never farther than the distance to the far corner would allow: a true bound of the ratio.
  for (float z : {3.0f, 10.0f, 50.0f})
    for (float x : {0.0f, 5.0f, 30.0f}) {
      const glm::vec3 eye(x, 0.5f, z);
      const float d = TerrainPass::vertical_error_distance(eye, lo, hi);
      for (float px : {-1.0f, 0.0f, 1.0f})
        for (float py : {-1.0f, 1.0f})
          for (float pz : {0.0f, 2.0f}) {
            const glm::vec3 v = glm::vec3(px, py, pz) - eye;
            const float h = std::hypot(v.x, v.y);
            EXPECT_LE(h / glm::dot(v, v), 1.0f / d * 1.0001f) << x << " " << z;
          }
    }
}

TEST(TerrainPass, GeometricErrorIsZeroOnPlanesAndGrowsWithStride) {
  assets::HeightField plane;
  plane.width = plane.height = 33;
  for (int y = 0; y < 33; ++y)
    for (int x = 0; x < 33; ++x) plane.heights.push_back(0.3f * x - 0.2f * y + 1.0f);
  for (int s = 1; s <= 32; s *= 2)
    EXPECT_NEAR(TerrainPass::chunk_error(plane, 0, 0, 32, 32, s), 0.0f, 1e-4f) << "stride " << s;

  const auto hills = test::make_hills(33, 1.0f);
  float previous = 0.0f;
  for (int s = 1; s <= 32; s *= 2) {
    const float e = TerrainPass::chunk_error(*hills, 0, 0, 32, 32, s);
    EXPECT_GE(e, previous * 0.5f) << "stride " << s;
    EXPECT_LE(e, 3.6f) << "bounded by the height range";
    previous = e;
  }
  EXPECT_EQ(TerrainPass::chunk_error(*hills, 0, 0, 32, 32, 1), 0.0f);
  EXPECT_GT(previous, 0.5f);
}

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
  EXPECT_EQ(lod_stats.terrain_chunks_drawn + lod_stats.terrain_chunks_culled, 64u);
  if (c.fraction() >= 0.01) {
    write_png(test::output_dir() + "/terrain_lod.png", *lod);
    write_png(test::output_dir() + "/terrain_lod.diff.png", c.diff);
  }
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

// A coarse budget (neighbours at levels 3 to 5) seen obliquely with the terrain filling the view
// and no sky: a crack between chunks shows the black clear colour. The hills are gentler than
// the view rays are steep, so a ray through a crack cannot meet the terrain again. (Without
// the skirts, 332 pixels are black here.)
TEST(TerrainPass, SkirtsCloseTheCracksBetweenLevels) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(256, 144);
  RenderPacket p = test::terrain_scene();
  p.view.sky = false;
  p.terrain.albedo = glm::vec3(1.0f);
  auto hills = std::make_shared<assets::HeightField>();
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
  EXPECT_GT(renderer.stats().terrain_chunks_drawn, 8u);
  if (black > 0) write_png(test::output_dir() + "/terrain_cracks.png", *image);
}

TEST(TerrainPass, ChunksOutsideTheViewAreCulled) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(64, 36);
  RenderPacket p = test::terrain_scene();
  p.terrain.heights = test::make_hills(129, 1.0f);  // 4 x 4 chunks, 128 m
  p.terrain.origin = {-64.0f, -64.0f, 0.0f};
  p.camera.position = {-60.0f, -60.0f, 3.0f};
  p.camera.target = {-70.0f, -70.0f, 0.0f};  // looking out over the corner
  renderer.render(p, target);
  renderer.wait_idle();
  EXPECT_GT(renderer.stats().terrain_chunks_culled, 10u);
  EXPECT_GE(renderer.stats().terrain_chunks_drawn, 1u);
}

}  // namespace
}  // namespace penumbra::render
