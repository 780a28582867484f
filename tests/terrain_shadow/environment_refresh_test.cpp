// EnvironmentRefresh (environment_refresh.h): the bound it skips tiles by holds against real
// shading, a turn too small to show re-shades nothing, and in the compose system a turned sky is
// spread over frames within the budget and converges to a whole shading bit for bit.
#include "penumbra/systems/terrain_shadow/environment_refresh.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "penumbra/assets/procedural.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/terrain.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_state.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

constexpr int N = kSystemBands;

glm::vec3 turn(const glm::vec3& d, float a) {
  return {std::cos(a) * d.x - std::sin(a) * d.y, std::sin(a) * d.x + std::cos(a) * d.y, d.z};
}

struct EnvScene {
  TerrainShadowing<N> shadowing{[] {
    TerrainShadowConfig c;
    c.azimuths = 16;
    return c;
  }()};
  sh::CoeffsRgb<N> sky{};
  glm::vec3 sun = glm::normalize(glm::vec3(0.8f, 0.3f, 0.25f));
  float sun_radius = 0.05f;
  glm::vec3 sun_irradiance{30.0f, 25.0f, 18.0f};
  std::vector<float> horizons;

  EnvScene() {
    shadowing.update(
        std::make_shared<data::HeightField>(assets::procedural_scene("mountains", {64, 128.0f}, 3)),
        1.0f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-0.6f, 0.6f);
    for (int c = 0; c < 3; ++c) {
      for (float& v : sky[c]) v = u(rng);
      sky[c][0] = 2.0f + 0.2f * c;
    }
    shadowing.key_light_horizons(sun, horizons);
  }
  // The environment and key light turned by `a` (horizons kept, as the system keeps them for
  // small turns).
  std::vector<glm::vec3> shade(float a) const {
    sh::CoeffsRgb<N> l;
    for (int c = 0; c < 3; ++c) l[c] = sh::rotate_z<N>(sky[c], a);
    std::vector<glm::vec3> e;
    shadowing.shade_environment(l, e);
    shadowing.add_key_light(turn(sun, a), sun_radius, sun_irradiance, horizons, e);
    return e;
  }
  EnvironmentPose pose(float a) const {
    sh::CoeffsRgb<N> l;
    for (int c = 0; c < 3; ++c) l[c] = sh::rotate_z<N>(sky[c], a);
    EnvironmentPose p;
    p.rotation = a;
    p.rotation_speed = rotation_speed_bound(l[0], l[1], l[2]);
    p.keys.push_back({turn(sun, a), sun_radius, luminance(sun_irradiance), horizons});
    return p;
  }
  std::vector<float> norms() const {
    std::vector<float> n;
    for (const auto& t : shadowing.transfer()) {
      float s = 0;
      for (float c : t) s += c * c;
      n.push_back(std::sqrt(s));
    }
    return n;
  }
};

TEST(EnvironmentRefresh, RotationSpeedBoundIsTheSpeedOfTheCoefficients) {
  sh::Coeffs<N> l{};
  l[1] = 1.0f;  // (1, -1)
  l[8] = 2.0f;  // (2, 2)
  const float g = rotation_speed_bound(l, l, l);
  EXPECT_NEAR(g, std::sqrt(1.0f + 4.0f * 4.0f), 1e-5f);  // luminance weights sum to 1
  // Against a finite difference of the rotation.
  const float d = 1e-3f;
  const auto a = sh::rotate_z<N>(l, 0.3f), b = sh::rotate_z<N>(l, 0.3f + d);
  float change = 0;
  for (int i = 0; i < static_cast<int>(a.size()); ++i) change += (b[i] - a[i]) * (b[i] - a[i]);
  EXPECT_NEAR(std::sqrt(change) / d, g, 1e-2f * g);
}

// For every tile the refresh leaves, the true change of every texel (environment + key light,
// shaded again) is within the tolerance of its irradiance; the check is not vacuous: small
// turns leave tiles, large ones re-shade most.
TEST(EnvironmentRefresh, SkippedTilesChangeByLessThanTheTolerance) {
  const EnvScene s;
  const std::vector<glm::vec3> before = s.shade(0.0f);
  EnvironmentRefreshConfig config;
  EnvironmentRefresh refresh(config);
  refresh.reset(64, 64, s.norms());
  ASSERT_EQ(refresh.plan(s.pose(0.0f), true).size(), 16u) << "unshaded: every tile";
  refresh.commit(s.pose(0.0f), s.shadowing.normals());
  refresh.set_reference(before);
  double mean = 0;
  for (const auto& e : before) mean += luminance(e);
  const float floor = config.dark_floor * static_cast<float>(mean / before.size());

  std::size_t small_left = 0, large_stale = 0;
  for (float a : {1e-5f, 1e-4f, 3e-4f, 1e-3f, 3e-3f, 1e-2f, 0.1f}) {
    const std::vector<TexelRect> stale = refresh.plan(s.pose(a), true);
    const std::vector<glm::vec3> after = s.shade(a);
    std::vector<bool> planned(before.size(), false);
    for (const TexelRect& r : stale)
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) planned[static_cast<std::size_t>(y) * 64 + x] = true;
    float worst = 0;
    for (std::size_t i = 0; i < before.size(); ++i) {
      if (planned[i]) continue;
      const float reference = std::max(luminance(before[i]), floor);
      worst = std::max(worst, std::abs(luminance(after[i]) - luminance(before[i])) / reference);
    }
    EXPECT_LE(worst, config.tolerance) << "turn " << a;
    if (a <= 1e-4f) small_left += 16 - stale.size();
    if (a >= 1e-2f) large_stale += stale.size();
  }
  EXPECT_EQ(refresh.plan(s.pose(1e-7f), true).size(), 0u) << "a turn too small to show";
  EXPECT_GE(small_left, 16u);
  EXPECT_GE(large_stale, 24u);
}

TEST(EnvironmentRefresh, BudgetAndNewHorizons) {
  const EnvScene s;
  EnvironmentRefresh refresh({16, 1.0f / 256.0f, 0.01f, 0.25f});
  refresh.reset(64, 64, s.norms());
  EXPECT_EQ(refresh.plan(s.pose(0.0f)).size(), 4u) << "a quarter of 16 tiles";
  EXPECT_EQ(refresh.stats().stale, 16u);
  refresh.commit(s.pose(0.0f), s.shadowing.normals());
  refresh.set_reference(s.shade(0.0f));
  EXPECT_EQ(refresh.plan(s.pose(0.0f)).size(), 4u) << "the never-shaded tiles come first";
  EnvironmentPose swept = s.pose(0.0f);
  swept.horizons_generation = 1;
  refresh.plan(s.pose(0.0f), true);
  refresh.commit(s.pose(0.0f), s.shadowing.normals());
  EXPECT_EQ(refresh.plan(swept, true).size(), 16u) << "new horizons: every tile";
  EXPECT_THROW(EnvironmentRefresh({0, 0.01f, 0.01f, 0.25f}), std::invalid_argument);
  EXPECT_THROW(EnvironmentRefresh({16, 0.01f, 0.01f, 0.0f}), std::invalid_argument);
  EXPECT_THROW(refresh.reset(64, 64, {}), std::invalid_argument);
}

// The compose system: a sky turned far re-shades at most the budget per frame, and once it
// stops converges to what a terrain shaded from the start at that rotation shows, bit for bit.
TEST(EnvironmentRefresh, TurnedSkyIsSpreadOverFramesAndConverges) {
  struct World {
    ecs::World world;
    jobs::Schedule schedule;
    jobs::Executor executor{2};
    ecs::Entity terrain;
    explicit World(float rotation) {
      TerrainShadowConfig config;
      config.azimuths = 8;
      emplace_terrain_shadow_resources(world, config);
      auto field = std::make_shared<data::HeightField>(
          assets::procedural_scene("mountains", {64, 128.0f}, 2));
      terrain = world.create_with(components::Terrain{field, {-64.0f, -64.0f, 0.0f}},
                                  components::TerrainLighting{});
      auto& env = world.emplace_resource<components::EnvironmentLight>();
      for (int c = 0; c < 3; ++c) {
        env.radiance[c][0] = 3.0f;
        env.radiance[c][1] = 1.0f;
        env.radiance[c][3] = -0.5f;
      }
      components::EnvironmentSource sun;
      sun.direction = glm::normalize(glm::vec3(1.0f, 0.2f, 0.4f));
      sun.angular_radius = 0.05f;
      sun.irradiance = glm::vec3(40.0f);
      env.sources = {sun};
      env.oem_sh.assign(2, env.radiance);
      env.version = 1;
      env.sources_version = 1;
      env.rotation_z = rotation;
      add_terrain_shadow_systems(schedule);
    }
    void frame() { executor.run(schedule, world); }
    const TerrainShadowState& state() { return *world.get<TerrainShadowState>(terrain); }
    const std::vector<glm::vec3>& rgb() {
      return *world.get<components::TerrainLighting>(terrain)->rgb;
    }
  };
  World turned(0.0f);
  turned.frame();
  EXPECT_EQ(turned.state().environment_refresh.stats().refreshed, 16u) << "first: all at once";
  turned.world.resource<components::EnvironmentLight>().rotation_z = 0.3f;
  std::size_t frames = 0;
  for (; frames < 12; ++frames) {
    const auto published = turned.world.get<components::TerrainLighting>(turned.terrain)->rgb;
    turned.frame();
    EXPECT_LE(turned.state().environment_refresh.stats().refreshed, 4u);
    if (turned.world.get<components::TerrainLighting>(turned.terrain)->rgb == published) break;
  }
  EXPECT_GE(frames, 4u) << "16 stale tiles, 4 a frame";
  EXPECT_LT(frames, 12u) << "did not converge";
  World fresh(0.3f);
  fresh.frame();
  EXPECT_EQ(turned.rgb(), fresh.rgb());
}

}  // namespace
}  // namespace penumbra::terrain_shadow
