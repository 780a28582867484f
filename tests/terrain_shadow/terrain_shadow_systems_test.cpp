// The terrain shadow systems in the job graph: what each frame recomputes, and what it skips.
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/frame_work.h"
#include "penumbra/assets/procedural.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/systems/terrain_shadow/terrain_edit.h"
#include "penumbra/systems/terrain_shadow/terrain_horizons.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_state.h"

namespace penumbra::terrain_shadow {
namespace {

using components::EnvironmentLight;
using components::SphericalLight;
using components::Terrain;
using components::TerrainLighting;

struct Fixture {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor{2};
  ecs::Entity terrain, light;

  Fixture() {
    TerrainShadowConfig config;
    config.azimuths = 8;
    config.light_azimuths = 8;
    emplace_terrain_shadow_resources(world, config);
    auto field =
        std::make_shared<data::HeightField>(assets::procedural_scene("mountains", {32, 64.0f}, 2));
    terrain = world.create_with(Terrain{field, {-32.0f, -32.0f, 0.0f}}, TerrainLighting{});
    light = world.create_with(SphericalLight{{0.0f, 0.0f, 60.0f}, 4.0f, glm::vec3(5.0f)});
    auto& env = world.emplace_resource<EnvironmentLight>();
    env.radiance[0][1] = env.radiance[1][1] = env.radiance[2][1] = 1.0f;  // a y-lobe: not zonal
    env.radiance[0][0] = env.radiance[1][0] = env.radiance[2][0] = 3.0f;
    env.version = 1;
    add_terrain_shadow_systems(schedule);
  }
  void frame() { executor.run(schedule, world); }
  // Frames until the lights are shaded everywhere (a quarter of the tiles per frame at most).
  void settle() {
    for (int i = 0; i < 8; ++i) {
      const std::uint64_t stamp = entry().lights_stamp;
      frame();
      if (entry().lights_stamp == stamp) return;
    }
    FAIL() << "the lights did not settle";
  }
  const TerrainShadowState& entry() {
    const TerrainShadowState* x = world.get<TerrainShadowState>(terrain);
    if (!x) throw std::runtime_error("the terrain has no TerrainShadowState");
    return *x;
  }
  const TerrainLighting& lighting() { return *world.get<TerrainLighting>(terrain); }
};

TEST(TerrainShadowSystems, SkipWhatDidNotChange) {
  Fixture f;
  f.frame();
  f.settle();
  ASSERT_TRUE(f.lighting().rgb);
  EXPECT_EQ(f.lighting().width, 32);
  EXPECT_TRUE(f.entry().last_update.full);
  const auto first = f.lighting().rgb;
  const auto visibility = f.entry().visibility_stamp, lights = f.entry().lights_stamp;
  f.frame();  // nothing changed: nothing recomputed, the same array stays published
  EXPECT_EQ(f.lighting().rgb, first);
  EXPECT_EQ(f.entry().visibility_stamp, visibility);
  EXPECT_EQ(f.entry().lights_stamp, lights);
}

TEST(TerrainShadowSystems, MovingLightReshadesWithoutEnvironmentVisibility) {
  Fixture f;
  f.frame();
  f.settle();
  const auto visibility = f.entry().visibility_stamp, lights = f.entry().lights_stamp;
  const auto before = f.lighting().rgb;
  f.world.get_mut<SphericalLight>(f.light)->position.x += 10.0f;
  f.frame();
  EXPECT_EQ(f.entry().visibility_stamp, visibility);
  EXPECT_EQ(f.entry().lights_stamp, lights + 1);
  EXPECT_NE(f.lighting().rgb, before);
  EXPECT_NE(*f.lighting().rgb, *before);
}

// The work each system reports to the frame table (jobs::report_work): a frame where nothing
// changed skips everything; a moved light, a turned sky, an edit each make their step work.
TEST(TerrainShadowSystems, ReportsTheWorkItSkipsPerFrame) {
  Fixture f;
  f.frame();
  f.settle();
  f.frame();
  auto step = [&](std::string_view name) {
    return penumbra::test::system_timing(f.executor.last_frame(), name);
  };
  for (const char* name :
       {"terrain_shadow.visibility", "terrain_shadow.lights", "terrain_shadow.compose"}) {
    EXPECT_TRUE(step(name).reported) << name;
    EXPECT_EQ(step(name).done, 0u) << name << ": nothing changed";
  }
  EXPECT_EQ(step("terrain_shadow.visibility").skipped, 1u);
  EXPECT_EQ(step("terrain_shadow.lights").skipped, 4u) << "every tile";
  EXPECT_EQ(step("terrain_shadow.compose").skipped, 1u);

  f.world.get_mut<SphericalLight>(f.light)->position.x += 10.0f;
  f.frame();
  EXPECT_EQ(step("terrain_shadow.visibility").skipped, 1u);
  EXPECT_GE(step("terrain_shadow.lights").done, 1u);
  EXPECT_EQ(step("terrain_shadow.lights").done + step("terrain_shadow.lights").skipped, 4u);
  EXPECT_EQ(step("terrain_shadow.compose").done, 1u);
  f.settle();

  f.world.resource<EnvironmentLight>().rotation_z = 0.5f;
  f.frame();
  EXPECT_EQ(step("terrain_shadow.lights").done, 0u);
  EXPECT_EQ(step("terrain_shadow.compose").done, 1u);

  ASSERT_TRUE(apply_brush(*f.world.get_mut<Terrain>(f.terrain),
                          {BrushKind::kCrater, {0.0f, 0.0f}, 6.0f, 8.0f}));
  f.frame();
  EXPECT_EQ(step("terrain_shadow.visibility").done, 1u);
  EXPECT_EQ(step("terrain_shadow.visibility").skipped, 0u);
  EXPECT_EQ(step("terrain_shadow.compose").done, 1u);
}

// A light that moved re-shades at most the budget (a quarter of the 4 tiles) per frame, then,
// once it stops, converges to a whole shading at its final place, bit for bit; a move too small
// to show re-shades nothing.
TEST(TerrainShadowSystems, MovedLightIsSpreadOverFramesAndConverges) {
  Fixture f;
  for (int i = 0; i < 4; ++i) f.frame();  // the first shading, a tile per frame
  EXPECT_EQ(f.entry().refresh.stats().tiles, 4u);
  f.world.get_mut<SphericalLight>(f.light)->position += glm::vec3(7.0f, -3.0f, -20.0f);
  int frames = 0;
  for (std::uint64_t stamp = f.entry().lights_stamp; frames < 20; ++frames) {
    f.frame();
    EXPECT_LE(f.entry().refresh.stats().refreshed, 1u);
    if (f.entry().lights_stamp == stamp) break;
    stamp = f.entry().lights_stamp;
  }
  EXPECT_GE(frames, 2);
  EXPECT_LE(frames, 4);
  TerrainShadowing<kSystemBands> whole(f.world.resource<TerrainShadowSettings>().config);
  const Terrain& t = *f.world.get<Terrain>(f.terrain);
  whole.update(t.heights, t.height_scale);
  std::vector<glm::vec3> expected;
  const SphericalLight& l = *f.world.get<SphericalLight>(f.light);
  whole.add_spherical_light(l.position - t.origin, l.radius, l.radiance, expected);
  EXPECT_EQ(f.entry().light_irradiance, expected);

  const auto stamp = f.entry().lights_stamp;
  f.world.get_mut<SphericalLight>(f.light)->position.x += 1e-4f;
  f.frame();
  EXPECT_EQ(f.entry().lights_stamp, stamp) << "a 0.1 mm move does not show";
}

// Among several lights, a re-shaded tile recomputes only the lights that changed there (their
// layers, TerrainShadowState::LightLayer), and the result is each light shaded alone, summed in
// light order (not one buffer shaded by both: the compiler's fused multiply-adds round that
// differently in the last bit).
TEST(TerrainShadowSystems, AMovingLightAmongStillOnesReshadesItself) {
  Fixture f;
  const ecs::Entity still =
      f.world.create_with(SphericalLight{{-10.0f, 8.0f, 40.0f}, 3.0f, glm::vec3(2.0f, 4.0f, 6.0f)});
  f.frame();
  f.settle();
  f.world.get_mut<SphericalLight>(f.light)->position += glm::vec3(9.0f, 5.0f, -15.0f);
  int frames = 0;
  for (std::uint64_t stamp = f.entry().lights_stamp; frames < 20; ++frames) {
    f.frame();
    if (f.entry().lights_stamp == stamp) break;
    EXPECT_EQ(f.entry().light_tile_shades, f.entry().refresh.stats().refreshed)
        << "one light per re-shaded tile, not two";
    stamp = f.entry().lights_stamp;
  }
  EXPECT_GE(frames, 2);
  TerrainShadowing<kSystemBands> whole(f.world.resource<TerrainShadowSettings>().config);
  const Terrain& t = *f.world.get<Terrain>(f.terrain);
  whole.update(t.heights, t.height_scale);
  std::vector<glm::vec3> expected(f.entry().light_irradiance.size(), glm::vec3(0.0f));
  for (ecs::Entity e : {f.light, still}) {  // creation order: the query's
    const SphericalLight& l = *f.world.get<SphericalLight>(e);
    std::vector<glm::vec3> alone;
    whole.add_spherical_light(l.position - t.origin, l.radius, l.radiance, alone);
    for (std::size_t i = 0; i < alone.size(); ++i) expected[i] += alone[i];
  }
  EXPECT_EQ(f.entry().light_irradiance, expected);
  // A light that goes away leaves the others' sum.
  f.world.destroy(f.light);
  f.settle();
  std::vector<glm::vec3> alone;
  const SphericalLight& l = *f.world.get<SphericalLight>(still);
  whole.add_spherical_light(l.position - t.origin, l.radius, l.radiance, alone);
  EXPECT_EQ(f.entry().light_irradiance, alone);
}

// EnvironmentLight::intensity scales the environment's share alone (the lights keep theirs),
// and changing it composes again without shading anything again.
TEST(TerrainShadowSystems, DimmingTheSkyScalesTheEnvironmentShareAlone) {
  Fixture f;
  f.frame();
  f.settle();
  const auto before = f.lighting().rgb;
  const auto lights = f.entry().lights_stamp, visibility = f.entry().visibility_stamp;
  f.world.resource<EnvironmentLight>().intensity = 0.25f;
  f.frame();
  EXPECT_EQ(f.entry().lights_stamp, lights);
  EXPECT_EQ(f.entry().visibility_stamp, visibility);
  ASSERT_NE(f.lighting().rgb, before);
  const auto& x = f.entry();
  for (std::size_t i = 0; i < x.composed.size(); i += 37) {
    const glm::vec3 want =
        glm::max(0.25f * x.environment_irradiance[i] + x.light_irradiance[i], glm::vec3(0.0f)) *
        std::numbers::inv_pi_v<float>;
    EXPECT_NEAR(x.composed[i].x, want.x, 1e-6f * (1 + want.x));
    EXPECT_LT((*f.lighting().rgb)[i].y, (*before)[i].y + 1e-6f);
  }
  const auto dimmed = f.lighting().rgb;
  f.frame();  // nothing changed: nothing composed again
  EXPECT_EQ(f.lighting().rgb, dimmed);
}

TEST(TerrainShadowSystems, RotatingEnvironmentReshadesFromStoredTransfer) {
  Fixture f;
  f.frame();
  f.settle();
  const auto visibility = f.entry().visibility_stamp, lights = f.entry().lights_stamp;
  const auto before = f.lighting().rgb;
  f.world.resource<EnvironmentLight>().rotation_z = std::numbers::pi_v<float> / 2;
  f.frame();
  EXPECT_EQ(f.entry().visibility_stamp, visibility);
  EXPECT_EQ(f.entry().lights_stamp, lights);
  ASSERT_NE(f.lighting().rgb, before);
  double diff = 0;
  for (std::size_t i = 0; i < before->size(); ++i)
    diff += std::abs((*before)[i].x - (*f.lighting().rgb)[i].x);
  EXPECT_GT(diff, 0.0);
}

// With sources in the environment (kKeyLights, the default): the SH part is the OEM without
// them and each source adds its key light; a turn by less than key_light_step of its radius
// keeps the swept horizons, a larger one sweeps again; kShOnly ignores the sources, and so does
// kKeyLights for a source wider than key_light_max_radius.
TEST(TerrainShadowSystems, EnvironmentSourcesBecomeKeyLights) {
  Fixture f;
  f.world.destroy(f.light);
  auto& env = f.world.resource<EnvironmentLight>();
  components::EnvironmentSource sun;
  sun.direction = glm::normalize(glm::vec3(1.0f, 0.2f, 0.5f));
  sun.angular_radius = 0.04f;
  sun.irradiance = glm::vec3(40.0f);
  env.sources = {sun};
  env.oem_sh.assign(2, env.radiance);  // set 1: the whole map; set 0: without the sun
  for (auto& c : env.oem_sh[0]) c[0] *= 0.5f;
  env.sources_version = env.version;
  f.frame();
  const auto with_sun = f.lighting().rgb;
  ASSERT_EQ(f.entry().key_lights.size(), 1u);
  const std::vector<float> swept = f.entry().key_lights[0].horizons;
  ASSERT_FALSE(swept.empty());

  f.world.resource<TerrainShadowSettings>().sources = EnvironmentSources::kShOnly;
  f.frame();
  const auto sh_only = f.lighting().rgb;
  ASSERT_NE(sh_only, with_sun);
  double lit = 0, plain = 0;
  for (std::size_t i = 0; i < sh_only->size(); ++i)
    lit += (*with_sun)[i].x, plain += (*sh_only)[i].x;
  EXPECT_NE(lit, plain);

  f.world.resource<TerrainShadowSettings>().sources = EnvironmentSources::kKeyLights;
  env.rotation_z = 0.2f * sun.angular_radius;  // under a quarter of the radius: same horizons
  f.frame();
  const float phi0 = f.entry().key_lights[0].phi;
  env.rotation_z = 0.3f;  // far more: swept again for the new azimuth
  f.frame();
  EXPECT_NE(f.entry().key_lights[0].phi, phi0);
  EXPECT_NE(f.entry().key_lights[0].horizons, swept);

  // A source wider than key_light_max_radius (a glow, not a sun) stays in the SH: as kShOnly.
  env.rotation_z = 0;
  env.sources[0].angular_radius = 0.5f;
  f.frame();
  const auto wide = f.lighting().rgb;
  ASSERT_EQ(wide->size(), sh_only->size());
  for (std::size_t i = 0; i < wide->size(); ++i) EXPECT_EQ((*wide)[i], (*sh_only)[i]) << i;
}

TEST(TerrainShadowSystems, BrushEditUpdatesIncrementally) {
  Fixture f;
  f.frame();
  Terrain& t = *f.world.get_mut<Terrain>(f.terrain);
  ASSERT_TRUE(apply_brush(t, {BrushKind::kCrater, {0.0f, 0.0f}, 6.0f, 8.0f}));
  f.frame();
  EXPECT_FALSE(f.entry().last_update.full);
  EXPECT_LT(f.entry().last_update.horizon_pairs, 32u * 32u * 8u);
  EXPECT_EQ(f.entry().version, 1u);
  // Two edits between frames: the system cannot know the first rectangle: full update.
  apply_brush(t, {BrushKind::kRaise, {5.0f, 5.0f}, 4.0f, 3.0f});
  apply_brush(t, {BrushKind::kRaise, {-9.0f, 5.0f}, 4.0f, 3.0f});
  f.frame();
  EXPECT_TRUE(f.entry().last_update.full);
}

// The state lives in component storage: it goes with the entity, and with the Terrain.
TEST(TerrainShadowSystems, StateGoesWithTheTerrain) {
  Fixture f;
  f.frame();
  ASSERT_NE(f.world.get<TerrainShadowState>(f.terrain), nullptr);
  const TerrainHorizons* h = f.world.get<TerrainHorizons>(f.terrain);
  ASSERT_NE(h, nullptr);
  EXPECT_EQ(h->horizons->width, 32);
  EXPECT_EQ(h->horizons->azimuths, 8);
  EXPECT_EQ(h->normals->size(), 32u * 32u);
  EXPECT_EQ(h->horizons.get(), &f.entry().shadowing->horizons()) << "published, not copied";
  f.world.remove<Terrain>(f.terrain);
  f.frame();
  EXPECT_EQ(f.world.get<TerrainShadowState>(f.terrain), nullptr);
  EXPECT_EQ(f.world.get<TerrainHorizons>(f.terrain), nullptr);

  Fixture g;
  g.frame();
  g.world.destroy(g.terrain);
  g.frame();
  std::size_t states = 0;
  g.world.query<const TerrainShadowState>().each([&](const TerrainShadowState&) { ++states; });
  EXPECT_EQ(states, 0u);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
