#include "penumbra/reference/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/stability.h"
#include "penumbra/reference/sampling.h"
#include "reference_test_util.h"

namespace penumbra::reference {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

void expect_invalid(const SceneDesc& d, const std::string& item, const std::string& why) {
  try {
    Scene s(d);
    ADD_FAILURE() << "no exception for " << item;
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(item), std::string::npos) << msg;
    EXPECT_NE(msg.find(why), std::string::npos) << msg;
  }
}

TEST(Scene, RejectsBadSpheresAndLightsNamingThem) {
  PENUMBRA_STABILITY("spheres and lights with NaN or negative radius",
                     "std::invalid_argument naming the item", "-");
  SceneDesc d;
  d.spheres = {{{0, 0, 0}, 1, "ok"}, {{0, 0, 5}, 0, "rock"}};
  expect_invalid(d, "spheres[1] \"rock\"", "radius 0 must be finite and > 0");
  d.spheres[1].radius = -2;
  expect_invalid(d, "spheres[1]", "radius");
  d.spheres[1] = {{kNaN, 0, 0}, 1, ""};
  expect_invalid(d, "spheres[1]", "center");
  d = {};
  d.lights = {{{0, 0, 3}, -1, {1, 1, 1}, "sun"}};
  expect_invalid(d, "lights[0] \"sun\"", "radius");
  d.lights[0] = {{0, kInf, 3}, 1, {1, 1, 1}, ""};
  expect_invalid(d, "lights[0]", "center");
  d.lights[0] = {{0, 0, 3}, 1, {1, -1, 1}, ""};
  expect_invalid(d, "lights[0]", "radiance");
  d.lights[0] = {{0, 0, 3}, kNaN, {1, 1, 1}, ""};
  expect_invalid(d, "lights[0]", "radius");
}

TEST(Scene, RejectsBadHeightFieldsMeshesAndMaps) {
  PENUMBRA_STABILITY("bad height fields, meshes and maps", "std::invalid_argument naming the item",
                     "-");
  SceneDesc d;
  d.height_fields.push_back({test::flat_field(4, 4, 1, 0), {0, 0, 0}});
  d.height_fields[0].field.heights[5] = kNaN;
  expect_invalid(d, "height_fields[0] \"flat\"", "(1, 1)");
  d.height_fields[0].field = test::flat_field(4, 4, 0, 0);
  expect_invalid(d, "height_fields[0]", "cell_size");
  d.height_fields[0].field = test::flat_field(1, 4, 1, 0);
  expect_invalid(d, "height_fields[0]", "2x2");
  d.height_fields[0].field = test::flat_field(4, 4, 1, 0);
  d.height_fields[0].field.heights.pop_back();
  expect_invalid(d, "height_fields[0]", "heights holds");
  d.height_fields[0] = {test::flat_field(4, 4, 1, 0), {kNaN, 0, 0}};
  expect_invalid(d, "height_fields[0]", "origin");

  d = {};
  d.meshes.push_back({test::quad(1, 0), glm::mat4(1)});
  d.meshes[0].mesh.indices.push_back(0);
  expect_invalid(d, "meshes[0] \"quad\"", "multiple of 3");
  d.meshes[0].mesh = test::quad(1, 0);
  d.meshes[0].mesh.indices[4] = 4;
  expect_invalid(d, "meshes[0]", "index 4 = 4");
  d.meshes[0].mesh = test::quad(1, 0);
  d.meshes[0].mesh.positions[2].y = kInf;
  expect_invalid(d, "meshes[0]", "position 2");
  d.meshes[0].mesh = test::quad(1, 0);
  d.meshes[0].transform[3][1] = kNaN;
  expect_invalid(d, "meshes[0]", "transform");

  d = {};
  d.environment = EnvironmentLight{test::constant_map(4, 2, glm::vec3(1)), 0};
  d.environment->map.rgb[2] = -1;
  expect_invalid(d, "environment map \"constant\"", "texel (0, 0)");
}

// Straight-down rays find the piecewise-linear surface of scene.h: cell (x, y)-(x+1, y+1)
// split along that diagonal.
TEST(Scene, HeightFieldIsTwoTrianglesPerCellOnTheMainDiagonal) {
  data::HeightField f = test::flat_field(3, 3, 2.0f, 0);
  f.at(1, 0) = 4;  // raise one corner of cell (0, 0)
  SceneDesc d;
  d.height_fields.push_back({f, {10, 20, 1}});
  const Scene s(d);
  EXPECT_EQ(s.triangle_count(), 8u);
  // Cell (0,0) corners: (0,0)=0, (1,0)=4, (0,1)=0, (1,1)=0. Lower-right triangle (a, b, d):
  // height = 4 * (u - v) at local (u, v) in [0,1]^2 with u > v; upper-left triangle: 0.
  auto height_at = [&](float u, float v) {
    const glm::vec3 o{10 + 2 * u, 20 + 2 * v, 100};
    return 100 - s.hit_distance(o, {0, 0, -1}, kInf) - 1;  // minus the origin's z
  };
  EXPECT_NEAR(height_at(0.75f, 0.25f), 4 * 0.5f, 1e-4f);
  EXPECT_NEAR(height_at(0.5f, 0.1f), 4 * 0.4f, 1e-4f);
  EXPECT_NEAR(height_at(0.25f, 0.75f), 0.0f, 1e-4f);
  EXPECT_NEAR(height_at(1.5f, 1.5f), 0.0f, 1e-4f);
  EXPECT_EQ(s.hit_distance({0, 0, 100}, {0, 0, -1}, kInf), kInf);  // outside the field
  EXPECT_FLOAT_EQ(s.extent(), 24.0f);  // max |coordinate|: y = 20 + 2 * 2
}

TEST(Scene, MeshTransformIsApplied) {
  SceneDesc d;
  glm::mat4 t(1.0f);
  t[3] = glm::vec4(5, 0, 2, 1);  // translate by (5, 0, 2)
  d.meshes.push_back({test::quad(1, 0), t});
  const Scene s(d);
  EXPECT_NEAR(s.hit_distance({5.5f, 0.5f, 10}, {0, 0, -1}, kInf), 8.0f, 1e-5f);
  EXPECT_EQ(s.hit_distance({0, 0, 10}, {0, 0, -1}, kInf), kInf);
  EXPECT_TRUE(s.occluded({5, 0, 0}, {0, 0, 1}, kInf));   // two-sided
  EXPECT_FALSE(s.occluded({5, 0, 0}, {0, 0, 1}, 1.9f));  // t_max before the quad
}

TEST(Scene, SpheresAreExactAndOccludeFromInside) {
  PENUMBRA_STABILITY("rays from inside an occluding sphere; grazing rays",
                     "every direction blocked from inside; grazing hits exact", "-");
  SceneDesc d;
  d.spheres = {{{0, 0, 10}, 2, "ball"}};
  d.lights = {{{0, 0, -10}, 3, {1, 1, 1}, "lamp"}};
  const Scene s(d);
  EXPECT_NEAR(s.hit_distance({0, 0, 0}, {0, 0, 1}, kInf), 8.0f, 1e-5f);
  // A ray grazing at distance 1.99 from the centre hits, at 2.01 misses.
  EXPECT_TRUE(s.occluded({1.99f, 0, 0}, {0, 0, 1}, kInf));
  EXPECT_FALSE(s.occluded({2.01f, 0, 0}, {0, 0, 1}, kInf));
  // From inside, every direction is blocked by the far side.
  Pcg32 rng(1, 0);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 w = uniform_sphere({rng.next_float(), rng.next_float()});
    EXPECT_TRUE(s.occluded({0.3f, -0.5f, 10.7f}, w, kInf));
  }
  // Lights are not occluders.
  EXPECT_FALSE(s.occluded({0, 0, 0}, {0, 0, -1}, kInf));
  EXPECT_EQ(s.lights().size(), 1u);
  EXPECT_EQ(s.environment(), nullptr);
}

// The automatic ray offset (1e-5 x scene extent along the normal, estimators.h) clears a large
// flat height field even for rays a hair above the horizon: no self-hits.
TEST(Scene, OffsetRaysDoNotHitTheirOwnSurface) {
  SceneDesc d;
  d.height_fields.push_back({test::flat_field(256, 256, 1.0f, 3.0f), {-100, -50, 0}});
  const Scene s(d);
  const float offset = 1e-5f * s.extent();
  Pcg32 rng(2, 0);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    // A sample point of the field, and a direction at elevation 1e-4 .. 1 rad.
    // (Kept 32 samples from the border so the downward rays below land on the field.)
    const glm::vec3 p{-100 + static_cast<float>(32 + rng.next_u32() % 192),
                      -50 + static_cast<float>(32 + rng.next_u32() % 192), 3.0f};
    const float elevation = std::pow(10.0f, -4 * rng.next_float());
    const float phi = 6.2831853f * rng.next_float();
    const glm::vec3 w{std::cos(elevation) * std::cos(phi), std::cos(elevation) * std::sin(phi),
                      std::sin(elevation)};
    hits += s.occluded(p + glm::vec3(0, 0, offset), w, kInf);
    // Below the horizon the surface is always found.
    EXPECT_TRUE(s.occluded(p + glm::vec3(0, 0, offset), {w.x, w.y, -w.z}, kInf));
  }
  EXPECT_EQ(hits, 0);
}

TEST(Scene, RejectsBadAlbedosNamingTheItem) {
  PENUMBRA_STABILITY("albedos non-finite, negative or above 1",
                     "std::invalid_argument naming the item", "-");
  SceneDesc d;
  d.spheres = {{{0, 0, 0}, 1, "ok", {1, 1, 1}}, {{0, 0, 5}, 1, "rock", {0.5f, 1.5f, 0}}};
  expect_invalid(d, "spheres[1] \"rock\"", "albedo (0.5, 1.5, 0) must be finite and in [0, 1]");
  d.spheres[1].albedo = {-0.1f, 0, 0};
  expect_invalid(d, "spheres[1]", "albedo");
  d = {};
  d.meshes.push_back({test::quad(1, 0), glm::mat4(1.0f), {0, kNaN, 0}});
  expect_invalid(d, "meshes[0] \"quad\"", "albedo");
  d = {};
  d.height_fields.push_back({test::flat_field(4, 4, 1, 0), {0, 0, 0}, {0, 0, kInf}});
  expect_invalid(d, "height_fields[0] \"flat\"", "albedo");
  d.height_fields[0].albedo = {0.2f, 0.3f, 0.4f};
  EXPECT_TRUE(Scene(d).reflects());
  d.height_fields[0].albedo = {};
  EXPECT_FALSE(Scene(d).reflects());
}

// first_hit: distance, the normal of the side hit (facing the ray) and the occluder's albedo.
TEST(Scene, FirstHitGivesDistanceFacingNormalAndAlbedo) {
  SceneDesc d;
  d.spheres = {{{0, 0, 10}, 2, "ball", {0.1f, 0.2f, 0.3f}}, {{20, 0, 0}, 1, "dark", {}}};
  // A unit quad rotated 90 degrees about +x (normal +z -> -y) and moved to y = 5.
  glm::mat4 t(1.0f);
  t[1] = {0, 0, 1, 0};
  t[2] = {0, -1, 0, 0};
  t[3] = {0, 5, 0, 1};
  d.meshes.push_back({test::quad(1, 0), t, {0.5f, 0.5f, 0.5f}});
  d.height_fields.push_back({test::flat_field(3, 3, 1, 0), {-40, -1, -3}, {1, 0, 0}});
  const Scene s(d);

  // Sphere from outside: near side, outward normal.
  const Hit a = s.first_hit({0, 0, 0}, {0, 0, 2}, kInf);  // |dir| = 2: distance in its units
  ASSERT_TRUE(a);
  EXPECT_NEAR(a.distance, 4.0f, 1e-5f);
  EXPECT_NEAR(a.normal.z, -1.0f, 1e-6f);
  EXPECT_EQ(a.albedo, glm::vec3(0.1f, 0.2f, 0.3f));
  // Off-axis: the normal is the radial direction at the hit point.
  const glm::vec3 dir = glm::normalize(glm::vec3(0.1f, 0.05f, 1));
  const Hit b = s.first_hit({0, 0, 0}, dir, kInf);
  ASSERT_TRUE(b);
  const glm::vec3 radial = glm::normalize(b.distance * dir - glm::vec3(0, 0, 10));
  EXPECT_NEAR(glm::dot(b.normal, radial), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::length(b.normal), 1.0f, 1e-6f);
  // From inside: the far side, normal pointing inwards (towards the origin of the ray).
  const Hit c = s.first_hit({0, 0, 10}, {0, 0, 1}, kInf);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c.distance, 2.0f, 1e-5f);
  EXPECT_NEAR(c.normal.z, -1.0f, 1e-6f);
  // Black sphere: a hit with zero albedo.
  const Hit black = s.first_hit({0, 0, 0}, {1, 0, 0}, kInf);
  ASSERT_TRUE(black);
  EXPECT_NEAR(black.distance, 19.0f, 1e-4f);
  EXPECT_EQ(black.albedo, glm::vec3(0));

  // Transformed quad from both sides: the normal of the transformed triangle, facing the ray.
  const Hit front = s.first_hit({0.2f, 0, 0.3f}, {0, 1, 0}, kInf);
  ASSERT_TRUE(front);
  EXPECT_NEAR(front.distance, 5.0f, 1e-5f);
  EXPECT_NEAR(front.normal.y, -1.0f, 1e-6f);
  EXPECT_EQ(front.albedo, glm::vec3(0.5f));
  const Hit back = s.first_hit({0.2f, 9, 0.3f}, {0, -1, 0}, kInf);
  ASSERT_TRUE(back);
  EXPECT_NEAR(back.distance, 4.0f, 1e-5f);
  EXPECT_NEAR(back.normal.y, 1.0f, 1e-6f);

  // Height field from above and below, oblique ray.
  const glm::vec3 down = glm::normalize(glm::vec3(0.3f, 0, -1));
  const Hit top = s.first_hit({-39.5f, 0, 0}, down, kInf);
  ASSERT_TRUE(top);
  EXPECT_NEAR(top.distance, 3 / -down.z, 1e-5f);
  EXPECT_NEAR(top.normal.z, 1.0f, 1e-6f);
  EXPECT_EQ(top.albedo, glm::vec3(1, 0, 0));
  const Hit under = s.first_hit({-38.5f, 0, -5}, -down, kInf);
  ASSERT_TRUE(under);
  EXPECT_NEAR(under.distance, 2 / -down.z, 1e-5f);
  EXPECT_NEAR(under.normal.z, -1.0f, 1e-6f);

  // Misses and t_max: a default Hit.
  const Hit miss = s.first_hit({0, 0, 0}, {0, 0, -1}, kInf);
  EXPECT_FALSE(miss);
  EXPECT_EQ(miss.distance, kInf);
  EXPECT_EQ(miss.normal, glm::vec3(0));
  EXPECT_FALSE(s.first_hit({0, 0, 0}, {0, 0, 1}, 7.9f));
  EXPECT_EQ(s.hit_distance({0, 0, 0}, {0, 0, 1}, kInf),
            s.first_hit({0, 0, 0}, {0, 0, 1}, kInf).distance);
}

TEST(Scene, EmptySceneHitsNothingAndMoves) {
  PENUMBRA_STABILITY("an empty scene", "hits nothing, extent 0", "-");
  Scene s(SceneDesc{});
  EXPECT_FALSE(s.occluded({0, 0, 0}, {0, 0, 1}, kInf));
  EXPECT_EQ(s.extent(), 0.0f);
  Scene moved(std::move(s));
  EXPECT_FALSE(moved.occluded({0, 0, 0}, {1, 0, 0}, kInf));
}

}  // namespace
}  // namespace penumbra::reference
