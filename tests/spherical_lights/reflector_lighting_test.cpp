#include "penumbra/systems/spherical_lights/reflector_lighting.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/constants.h"
#include "test_meshes.h"

namespace penumbra::spherical_lights {
namespace {

sh::CoeffsRgb<4> white_sky(float radiance) {
  sh::CoeffsRgb<4> sky{};
  for (int c = 0; c < 3; ++c) sky[c][0] = radiance * kSqrt4Pi;
  return sky;
}

TEST(ReflectorLighting, AnUnshadowedBoxUnderAUniformSkyReflectsItsAlbedo) {
  // Each face point sees half the sky: E = pi L; reflected without albedo E / pi = L; the SL's
  // radiance is albedo x L wherever it has points (all 92 directions here).
  const data::MeshData box =
      test::box_mesh(glm::vec3(-1), glm::vec3(1), glm::vec3(0.5f, 0.25f, 1.0f));
  const std::vector<data::Sphere> spheres = {{glm::vec3(0), std::sqrt(3.0f) + 1e-3f, -1}};
  const ReflectorSamples samples = sample_reflector(box, spheres);
  const ReflectorLighting<4> lighting(samples.directions);
  blocker_accumulation::BlockerAccumulation<4> none;
  none.set_blockers({});
  std::vector<std::vector<glm::vec3>> reflected;
  const std::vector<sh::CoeffsRgb<4>> radiance =
      lighting.update(samples, {}, none, white_sky(2.0f), &reflected);
  ASSERT_EQ(radiance.size(), 1u);
  for (const glm::vec3& v : reflected[0]) EXPECT_NEAR(v.x, 2.0f, 0.02f);
  // L^c's mean over the sphere: albedo x 2 (the SH product of two near-constants).
  EXPECT_NEAR(radiance[0][0][0] / kSqrt4Pi, 1.0f, 0.02f);
  EXPECT_NEAR(radiance[0][1][0] / kSqrt4Pi, 0.5f, 0.01f);
  EXPECT_NEAR(radiance[0][2][0] / kSqrt4Pi, 2.0f, 0.04f);
}

TEST(ReflectorLighting, AnotherObjectsShadowDarkensTheSamplePointsBehindIt) {
  const data::MeshData box = test::box_mesh(glm::vec3(-1), glm::vec3(1));
  const std::vector<data::Sphere> spheres = {{glm::vec3(0), std::sqrt(3.0f) + 1e-3f, -1}};
  const ReflectorSamples samples = sample_reflector(box, spheres);
  const ReflectorLighting<4> lighting(samples.directions);
  blocker_accumulation::BlockerAccumulation<4> wall;
  wall.set_blockers({{glm::vec3(0, 0, 4), 2.5f}});  // a big sphere above the box
  std::vector<std::vector<glm::vec3>> reflected;
  lighting.update(samples, {}, wall, white_sky(1.0f), &reflected);
  float top = 0, bottom = 0;
  int n_top = 0, n_bottom = 0;
  for (std::size_t j = 0; j < samples.directions.size(); ++j) {
    if (samples.lights[0].normals[j].z > 0.9f) top += reflected[0][j].x, ++n_top;
    if (samples.lights[0].normals[j].z < -0.9f) bottom += reflected[0][j].x, ++n_bottom;
  }
  ASSERT_GT(n_top, 0);
  ASSERT_GT(n_bottom, 0);
  EXPECT_LT(top / static_cast<float>(n_top), 0.8f * bottom / static_cast<float>(n_bottom));
}

TEST(ReflectorLighting, RotatingTheObjectTurnsItsLightWithIt) {
  // A light bright on its +x side only, then the object turned 180 degrees about z: receivers on
  // -x now see the bright side ([Guerrero08] sec. 7.1, the weights turned by the inverse).
  const std::vector<glm::vec3> dirs = geodesic_directions(3);
  const ReflectorLighting<4> lighting(dirs);
  std::vector<glm::vec3> values;
  for (const glm::vec3& d : dirs) values.push_back(glm::vec3(d.x > 0 ? 1.0f : 0.0f));
  const sh::CoeffsRgb<4> half = lighting.cells().project(values);
  ReflectorSamples object;
  object.directions = dirs;
  object.lights.resize(1);
  object.lights[0].centre = glm::vec3(0);
  object.lights[0].radius = 1;
  SphereLightSettings s;
  s.blocker.min_sin = 0;
  SphereLightGather<4> gather(s);
  std::vector<SphereLightSource<4>> lights;
  ObjectPose pose;
  pose.translation = glm::vec3(0, 0, 0);
  ReflectorLighting<4>::place(object, pose, std::span(&half, 1), 0, lights);
  gather.set_lights(lights);
  const float plus = gather.irradiance(glm::vec3(4, 0, 0), glm::vec3(-1, 0, 0)).x;
  const float minus = gather.irradiance(glm::vec3(-4, 0, 0), glm::vec3(1, 0, 0)).x;
  EXPECT_GT(plus, 3 * minus);
  lights.clear();
  pose.rotation = glm::mat3(glm::vec3(-1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1));
  pose.translation = glm::vec3(0.5f, 0, 0);
  pose.scale = 2;
  ReflectorLighting<4>::place(object, pose, std::span(&half, 1), 0, lights);
  EXPECT_EQ(lights[0].centre, glm::vec3(0.5f, 0, 0));
  EXPECT_EQ(lights[0].radius, 2.0f);
  gather.set_lights(lights);
  const float plus_turned = gather.irradiance(glm::vec3(8.5f, 0, 0), glm::vec3(-1, 0, 0)).x;
  const float minus_turned = gather.irradiance(glm::vec3(-7.5f, 0, 0), glm::vec3(1, 0, 0)).x;
  EXPECT_GT(minus_turned, 3 * plus_turned);
  EXPECT_NEAR(minus_turned, plus, 1e-4f);  // twice the size at twice the distance: same angle
}

}  // namespace
}  // namespace penumbra::spherical_lights
