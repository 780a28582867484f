// LightRefresh: the change bound holds against real shading, unchanged lights re-shade nothing,
// the budget spreads a light over frames, and region shading equals full shading bit for bit.
#include "penumbra/systems/terrain_shadow/light_refresh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "common/stability.h"
#include "penumbra/systems/terrain_shadow/cap_transfer.h"
#include "penumbra/systems/terrain_shadow/light_horizon_march.h"
#include "penumbra/systems/terrain_shadow/radial_horizon_sweep.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

std::vector<glm::vec3> positions(const TerrainShadowing<4>& s) {
  std::vector<glm::vec3> p;
  for (int y = 0; y < s.field().height; ++y)
    for (int x = 0; x < s.field().width; ++x) p.push_back(s.position(x, y));
  return p;
}

// 64 x 64 mountains (2 m cells: 16 tiles) and a refresh for them with `budget`.
struct Scene {
  TerrainShadowing<4> shadowing;
  LightRefresh refresh;
  explicit Scene(float budget) : refresh({16, 1.0f / 256.0f, 0.01f, budget}) {
    shadowing.update(test::mountains(64, 5), 1.0f);
    refresh.reset(64, 64, positions(shadowing));
  }
};

TEST(LightRefresh, SolidAngleOfASphere) {
  EXPECT_NEAR(sphere_solid_angle(1.0f, 1000.0f), kPi * 1e-6f, 1e-10f);  // pi (r / d)^2
  EXPECT_NEAR(sphere_solid_angle(1.0f, 2.0f), 2 * kPi * (1 - std::sqrt(0.75f)), 1e-6f);
  EXPECT_EQ(sphere_solid_angle(2.0f, 1.0f), 2 * kPi) << "inside";
  const LightSample l{{0, 0, 0}, 1.0f, glm::vec3(2.0f)};
  EXPECT_NEAR(light_irradiance_bound(l, 100.0f), 2.0f * kPi * 1e-4f, 1e-7f);
  EXPECT_EQ(light_change_bound(l, l, 10.0f), 0.0f) << "nothing changed";
  LightSample brighter = l;
  brighter.radiance *= 2.0f;
  EXPECT_NEAR(light_change_bound(l, brighter, 100.0f), 2.0f * sphere_solid_angle(1, 100), 1e-7f);
  EXPECT_EQ(light_change_bound(l, brighter, 0.5f), kPi * 4.0f) << "inside: pi L_max";
}

// Moves, grows and recolours a light over mountains and checks the bound against the real
// change of every texel's shading, occlusion included.
TEST(LightRefresh, ChangeBoundHoldsAgainstShading) {
  TerrainShadowing<4> s;
  s.update(test::mountains(48, 3), 1.0f);
  const std::vector<glm::vec3> pos = positions(s);
  const LightSample base{{40.0f, 50.0f, 30.0f}, 3.0f, {4.0f, 3.0f, 2.0f}};
  const LightSample changes[] = {
      {{41.0f, 50.0f, 30.0f}, 3.0f, {4.0f, 3.0f, 2.0f}},  // 1 m sideways
      {{40.0f, 50.0f, 26.0f}, 3.0f, {4.0f, 3.0f, 2.0f}},  // 4 m down, towards the terrain
      {{40.0f, 50.0f, 30.0f}, 3.5f, {4.0f, 3.0f, 2.0f}},  // larger
      {{40.0f, 50.0f, 30.0f}, 3.0f, {2.0f, 3.5f, 2.0f}},  // another colour
      {{55.0f, 30.0f, 12.0f}, 2.0f, {8.0f, 6.0f, 1.0f}},  // all of it, far
  };
  std::vector<glm::vec3> before;
  s.add_spherical_light(base.centre, base.radius, base.radiance, before);
  for (const LightSample& after : changes) {
    std::vector<glm::vec3> now;
    s.add_spherical_light(after.centre, after.radius, after.radiance, now);
    float tightest = 0;
    for (std::size_t i = 0; i < pos.size(); ++i) {
      // Distance from the receiver to the segment between the centres.
      const glm::vec3 ab = after.centre - base.centre;
      const float ab2 = glm::dot(ab, ab);
      const float t =
          ab2 > 0 ? std::clamp(glm::dot(pos[i] - base.centre, ab) / ab2, 0.0f, 1.0f) : 0.0f;
      const float d = glm::length(pos[i] - (base.centre + t * ab));
      const float change = std::abs(luminance(now[i]) - luminance(before[i]));
      const float bound = light_change_bound(base, after, d);
      ASSERT_LE(change, bound * 1.001f + 1e-6f) << "texel " << i;
      if (bound > 0) tightest = std::max(tightest, change / bound);
    }
    EXPECT_GT(tightest, 0.02f) << "the bound is within 50x of the change somewhere";
  }
}

TEST(LightRefresh, UnchangedLightsReshadeNothingAndSmallMovesOnlyNearTiles) {
  Scene scene(1.0f);
  TerrainShadowing<4>& s = scene.shadowing;
  LightRefresh& r = scene.refresh;
  std::vector<LightSample> lights = {{{10.0f, 10.0f, 20.0f}, 2.0f, glm::vec3(20.0f)}};
  EXPECT_EQ(r.plan(lights).size(), 16u) << "never shaded: every tile";
  std::vector<glm::vec3> e(64 * 64, glm::vec3(0.0f));
  for (const LightSample& l : lights)
    s.add_spherical_light(l.centre, l.radius, l.radiance, e, r.plan(lights));
  r.commit();
  for (glm::vec3& v : e) v += glm::vec3(1.0f);  // an environment of irradiance 1
  r.set_reference(e);
  EXPECT_TRUE(r.plan(lights).empty()) << "nothing changed";
  lights[0].centre.x += 0.05f;
  const std::size_t near = r.plan(lights).size();
  EXPECT_GT(near, 0u);
  EXPECT_LT(near, 8u) << "a 5 cm move shows only near the light";
  for (const TexelRect& t : r.plan(lights))
    EXPECT_LT(glm::length(glm::vec2(t.x0 + 8, t.y0 + 8) * 2.0f - glm::vec2(10.0f)), 70.0f);
}

TEST(LightRefresh, BudgetSpreadsALightWorstFirstAndConverges) {
  Scene scene(0.25f);
  TerrainShadowing<4>& s = scene.shadowing;
  LightRefresh& r = scene.refresh;
  const std::vector<LightSample> lights = {{{60.0f, 60.0f, 15.0f}, 2.0f, glm::vec3(20.0f)}};
  std::vector<glm::vec3> e(64 * 64, glm::vec3(0.0f));
  int frames = 0;
  for (; frames < 10; ++frames) {
    const std::vector<TexelRect>& tiles = r.plan(lights);
    if (tiles.empty()) break;
    std::size_t texels = 0;
    for (const TexelRect& t : tiles) texels += t.count();
    EXPECT_LE(texels, 64u * 64u / 4) << "frame " << frames;
    if (frames == 0) {  // the brightest first: the tile under the light
      EXPECT_TRUE(tiles.front().contains(30, 30)) << tiles.front().x0 << ", " << tiles.front().y0;
    }
    for (const LightSample& l : lights)
      s.add_spherical_light(l.centre, l.radius, l.radiance, e, tiles);
    r.commit();
  }
  EXPECT_EQ(frames, 4) << "16 tiles, 4 a frame";
  std::vector<glm::vec3> full;
  s.add_spherical_light(lights[0].centre, lights[0].radius, lights[0].radiance, full);
  EXPECT_EQ(e, full) << "tiles shaded apart equal the whole light, bit for bit";
  EXPECT_EQ(r.stats().frames_shaded, 4u);
}

TEST(LightRefresh, RegionShadingEqualsFullShading) {
  for (const CapHorizons cap : {CapHorizons::kRadialSweep, CapHorizons::kMarch}) {
    TerrainShadowConfig config;
    config.cap_method = cap;
    TerrainShadowing<4> s(config);
    s.update(test::mountains(40, 7), 1.0f);
    const glm::vec3 c(20.0f, 35.0f, 12.0f);
    std::vector<glm::vec3> full;
    s.add_spherical_light(c, 1.5f, glm::vec3(3.0f), full);
    const TexelRect regions[] = {{0, 0, 16, 16}, {24, 30, 40, 40}, {35, 2, 50, 9}};  // one clipped
    std::vector<glm::vec3> part(full.size(), glm::vec3(-1.0f));
    for (const TexelRect& r : regions)
      for (int y = r.y0; y < std::min(r.y1, 40); ++y)
        for (int x = r.x0; x < std::min(r.x1, 40); ++x) part[y * 40 + x] = glm::vec3(0.0f);
    s.add_spherical_light(c, 1.5f, glm::vec3(3.0f), part, regions);
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) {
        bool inside = false;
        for (const TexelRect& r : regions) inside = inside || r.contains(x, y);
        if (inside)
          ASSERT_EQ(part[y * 40 + x], full[y * 40 + x]) << x << ", " << y;
        else
          ASSERT_EQ(part[y * 40 + x], glm::vec3(-1.0f)) << "untouched " << x << ", " << y;
      }
    std::vector<glm::vec3> wrong(3);
    EXPECT_THROW(s.add_spherical_light(c, 1.5f, glm::vec3(3.0f), wrong, regions),
                 std::invalid_argument);
  }
}

TEST(LightRefresh, RadialSweepWithinItsReachEqualsTheWholeSweep) {
  const auto field = test::mountains(48, 9);
  RadialHorizonSweep whole, near;
  const glm::vec2 foot(30.0f, 52.0f);
  whole.run(*field, 1.0f, foot);
  near.run(*field, 1.0f, foot, 20.0f);
  int compared = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x)
      if (glm::length(glm::vec2(x, y) * field->cell_size - foot) <= 20.0f) {
        ASSERT_EQ(near.horizon(x, y), whole.horizon(x, y)) << x << ", " << y;
        ++compared;
      }
  EXPECT_GT(compared, 200);
}

TEST(LightRefresh, RejectsBadSettingsAndSizes) {
  PENUMBRA_STABILITY("tile 0, budget 0, negative tolerance; positions not width x height",
                     "std::invalid_argument", "-");
  EXPECT_THROW(LightRefresh({0, 0.01f, 0.01f, 0.5f}), std::invalid_argument);
  EXPECT_THROW(LightRefresh({16, 0.01f, 0.01f, 0.0f}), std::invalid_argument);
  EXPECT_THROW(LightRefresh({16, -1.0f, 0.01f, 0.5f}), std::invalid_argument);
  LightRefresh r;
  EXPECT_THROW(r.reset(4, 4, std::vector<glm::vec3>(15)), std::invalid_argument);
  EXPECT_THROW(r.reset(0, 4, {}), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
