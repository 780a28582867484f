// End to end: a terrain lit by the terrain shadow systems (ECS, job graph) drawn through the
// render extract and the renderer on lavapipe, against a golden image (render_test_util.h).
// An egg tray under a low directional sky and a spherical light: the cups' soft shadows
// and the light's pool must both show.
#include <gtest/gtest.h>

#include "penumbra/assets/procedural.h"
#include "penumbra/components/camera.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/render/offscreen_target.h"
#include "penumbra/render/renderer.h"
#include "penumbra/sh/projection.h"
#include "penumbra/systems/render_extract/render_extract.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"
#include "render_test_util.h"

namespace penumbra {
namespace {

TEST(Golden, TerrainShadowedByTheTerrainShadowSystem) {
  ecs::World w;
  systems::emplace_render_resources(w);
  // The golden is of the lighting: the terrain at full detail, whatever the level of detail does.
  w.resource<systems::RenderSettings>().view.terrain_lod_pixels = 0.0f;
  terrain_shadow::emplace_terrain_shadow_resources(w);
  auto& cam = w.emplace_resource<components::Camera>();
  cam.position = {0.0f, -80.0f, 60.0f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.vertical_fov = 0.9f;
  auto field =
      std::make_shared<data::HeightField>(assets::procedural_scene("egg_tray", {64, 96.0f}, 1));
  w.create_with(components::Terrain{field, {-48.0f, -48.0f, 0.0f}, glm::vec3(0.6f), 1.5f},
                components::TerrainLighting{});
  w.create_with(components::SphericalLight{{20.0f, -10.0f, 16.0f}, 3.0f, {30.0f, 18.0f, 6.0f}});
  // The environment: the test map of render_test_util.h (sky gradient with a sun) as 4-band SH.
  const auto map = render::test::make_environment(64, 32);
  auto& env = w.emplace_resource<components::EnvironmentLight>();
  env.map = map;
  env.radiance = sh::project_equirect<sh::kDefaultBands>(map->rgb.data(), map->width, map->height);
  env.version = 1;

  jobs::Schedule schedule;
  terrain_shadow::add_terrain_shadow_systems(schedule);
  systems::add_render_extract(schedule);
  jobs::Executor executor(2);
  // The light is shaded a quarter of the terrain per frame at most (light_refresh.h): 4 frames.
  for (int frame = 0; frame < 4; ++frame) executor.run(schedule, w);
  const render::RenderPacket& packet = w.resource<render::RenderPacket>();
  ASSERT_TRUE(packet.terrain.lighting);

  render::test::TestContext ctx;
  render::Renderer renderer(ctx.device);
  render::OffscreenTarget target(128, 72);
  const auto image = renderer.capture(packet, target);
  ASSERT_TRUE(image.has_value());
  render::test::expect_matches_golden(*image, "terrain_shadow_system");
  EXPECT_EQ(ctx.instance.messages().total(), 0u) << ctx.instance.messages().summary();
}

}  // namespace
}  // namespace penumbra
