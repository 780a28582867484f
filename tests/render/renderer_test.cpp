#include "penumbra/render/renderer.h"

#include <gtest/gtest.h>

#include "common/stability.h"
#include "penumbra/render/offscreen_target.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

RenderPacket everything() {
  RenderPacket p = test::terrain_scene();
  const RenderPacket m = test::mesh_scene();
  const RenderPacket d = test::debug_scene();
  p.meshes = m.meshes;
  p.spheres = d.spheres;
  p.lines = d.lines;
  p.points = d.points;
  p.sky.environment = test::make_environment(32, 16);
  return p;
}

// Renders frames with validation on: every pass, uploads replaced in place and with new sizes,
// captures, a resize and skipped frames. Any validation message fails the test.
TEST(Renderer, FramesWithValidationReportNoMessages) {
  test::TestContext ctx;
  {
    Renderer renderer(ctx.device);
    OffscreenTarget target(96, 64);
    RenderPacket p = everything();
    for (int frame = 0; frame < 12; ++frame) {
      if (frame == 3) p.terrain.lighting = test::make_lighting(32, 32);  // same size: in place
      if (frame == 4) {                                                  // new size: new image
        p.terrain.lighting = test::make_lighting(16, 8);
        p.terrain.lighting_width = 16;
        p.terrain.lighting_height = 8;
      }
      if (frame == 5) p.terrain.heights = test::make_hills(20, 1.5f);  // new grid
      if (frame == 6) p.terrain.heights = test::make_hills(20, 1.0f);  // same grid: in place
      if (frame == 7) target.resize(64, 40);
      if (frame == 8) p.sky.environment = test::make_environment(16, 8);
      if (frame == 9) p.meshes.clear();
      if (frame % 4 == 1) {
        ASSERT_TRUE(renderer.capture(p, target).has_value());
      } else {
        EXPECT_EQ(renderer.render(p, target), FrameStatus::kRendered);
      }
    }
    renderer.wait_idle();
    EXPECT_FALSE(renderer.last_pass_times().empty());
  }
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

TEST(Renderer, ZeroSizedTargetSkipsFrames) {
  PENUMBRA_STABILITY("a zero-sized (minimised) target",
                     "frames skipped and counted, no validation message", "-");
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(0, 0);
  const RenderPacket p = test::debug_scene();
  EXPECT_EQ(renderer.render(p, target), FrameStatus::kSkipped);
  EXPECT_FALSE(renderer.capture(p, target).has_value());
  target.resize(32, 16);
  const auto image = renderer.capture(p, target);
  ASSERT_TRUE(image.has_value());
  EXPECT_EQ(image->width, 32);
  EXPECT_EQ(renderer.stats().skipped, 2u);
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

TEST(Renderer, ReportsGpuTimePerPass) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(64, 36);
  const RenderPacket p = everything();
  for (int i = 0; i < 6; ++i) renderer.render(p, target);
  renderer.wait_idle();
  std::vector<std::string> names;
  for (const PassTime& t : renderer.last_pass_times()) {
    names.emplace_back(t.name);
    EXPECT_GE(t.ms, 0.0) << t.name;
  }
  const std::vector<std::string> expected = {"upload", "terrain", "meshes", "debug",
                                             "sky",    "tonemap", "output"};
  EXPECT_EQ(names, expected);
  EXPECT_EQ(renderer.pass_table().frames(), 6u);
  EXPECT_GT(renderer.pass_table().mean_total_ms(), 0.0);
}

// set_timing_interval(3): frames 3 and 6 of six are timed; 0: none. An untimed frame draws the
// scene passes in one rendering scope, a timed one in one scope each: the same image.
TEST(Renderer, TimesOneFrameInTheInterval) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(64, 36);
  const RenderPacket p = everything();
  renderer.set_timing_interval(3);
  for (int i = 0; i < 6; ++i) renderer.render(p, target);
  renderer.wait_idle();
  EXPECT_EQ(renderer.pass_table().frames(), 2u);
  renderer.set_timing_interval(0);
  renderer.pass_table().clear();
  for (int i = 0; i < 4; ++i) renderer.render(p, target);
  renderer.wait_idle();
  EXPECT_EQ(renderer.pass_table().frames(), 0u);
  const auto untimed = renderer.capture(p, target);
  renderer.set_timing_interval(1);
  const auto timed = renderer.capture(p, target);
  ASSERT_TRUE(untimed && timed);
  EXPECT_EQ(renderer.pass_table().frames(), 1u);
  EXPECT_EQ(untimed->pixels, timed->pixels);
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

TEST(Renderer, DisabledPassesDrawNothing) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(32, 18);
  RenderPacket p = everything();
  p.view.sky = p.view.terrain = p.view.meshes = p.view.debug = false;
  const auto image = renderer.capture(p, target);
  ASSERT_TRUE(image.has_value());
  for (std::size_t i = 0; i < image->pixels.size(); i += 4)
    ASSERT_EQ(image->pixels[i] + image->pixels[i + 1] + image->pixels[i + 2], 0)
        << "pixel " << i / 4;
}

TEST(Renderer, MeshCacheUploadsOnceAndEvictsUnusedMeshes) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(32, 18);
  RenderPacket p = test::mesh_scene();  // two draws of one mesh
  renderer.render(p, target);
  EXPECT_EQ(renderer.stats().cached_meshes, 1u);
  const ObjectCounts with_mesh = ctx.device.object_counts();
  for (int i = 0; i < 5; ++i) renderer.render(p, target);
  EXPECT_EQ(ctx.device.object_counts(), with_mesh) << "no per-frame allocations";
  p.meshes.clear();
  for (std::uint64_t i = 0; i < MeshPass::kEvictAfterFrames + Renderer::kFramesInFlight + 2; ++i)
    renderer.render(p, target);
  renderer.wait_idle();
  EXPECT_EQ(renderer.stats().cached_meshes, 0u);
  EXPECT_EQ(renderer.stats().retired, 0u);
  const auto buffers = static_cast<int>(ObjectKind::kBuffer);
  EXPECT_EQ(ctx.device.object_counts().live[buffers], with_mesh.live[buffers] - 2);
}

TEST(Renderer, RejectsMeshesWithIndicesOutOfRange) {
  PENUMBRA_STABILITY("a mesh with indices out of range",
                     "the mesh rejected and counted; the frame renders", "-");
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(32, 18);
  RenderPacket p;
  auto bad = std::make_shared<data::MeshData>();
  bad->positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bad->indices = {0, 1, 3};
  MeshDraw d;
  d.mesh = bad;
  p.meshes.push_back(d);
  EXPECT_EQ(renderer.render(p, target), FrameStatus::kRendered);
  renderer.wait_idle();
  EXPECT_EQ(renderer.stats().rejected_meshes, 1u);
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

// glTF's convention: counter-clockwise triangles, seen from outside, are front faces; the mesh
// pass culls back faces.
TEST(Renderer, MeshesCullClockwiseBackFaces) {
  test::TestContext ctx;
  Renderer renderer(ctx.device);
  OffscreenTarget target(32, 32);
  RenderPacket p;
  p.view.sky = false;
  auto ccw = std::make_shared<data::MeshData>();
  ccw->positions = {{-1, 0, -1}, {1, 0, -1}, {-1, 0, 1}};  // CCW seen from -y, the camera
  ccw->indices = {0, 1, 2};
  MeshDraw d;
  d.mesh = ccw;
  d.vertex_lighting = std::make_shared<std::vector<glm::vec3>>(3, glm::vec3(1));
  p.meshes.push_back(d);
  p.camera.position = {0, -5, 0};
  auto lit = [&] {
    const auto image = renderer.capture(p, target);
    int n = 0;
    for (std::size_t i = 0; i < image->pixels.size(); i += 4) n += image->pixels[i] > 100;
    return n;
  };
  EXPECT_GT(lit(), 40) << "front face drawn";
  auto cw = std::make_shared<data::MeshData>(*ccw);
  cw->indices = {0, 2, 1};
  p.meshes[0].mesh = cw;
  EXPECT_EQ(lit(), 0) << "back face culled";
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

}  // namespace
}  // namespace penumbra::render
