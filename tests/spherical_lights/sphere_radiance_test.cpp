#include "penumbra/systems/spherical_lights/sphere_radiance.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "common/constants.h"
#include "penumbra/systems/spherical_lights/reflector_samples.h"

namespace penumbra::spherical_lights {
namespace {

TEST(VoronoiCellSums, CellsPartitionTheDirectionsAndAConstantProjectsToAConstant) {
  const std::vector<glm::vec3> dirs = geodesic_directions(3);
  const VoronoiCellSums<4> cells(dirs, 64);
  int total = 0;
  for (int j = 0; j < cells.cells(); ++j) {
    total += cells.count(j);
    EXPECT_GT(cells.count(j), 60) << j;  // 8,192 / 92 = 89 on average
  }
  EXPECT_EQ(total, cells.directions());
  EXPECT_EQ(total, 2 * 64 * 64);
  const std::vector<glm::vec3> ones(dirs.size(), glm::vec3(2.0f, 1.0f, 0.5f));
  const sh::CoeffsRgb<4> f = cells.project(ones);
  EXPECT_NEAR(f[0][0], 2.0f * kSqrt4Pi, 1e-3f);
  EXPECT_NEAR(f[2][0], 0.5f * kSqrt4Pi, 1e-3f);
  for (int i = 1; i < 16; ++i) EXPECT_NEAR(f[0][i], 0.0f, 0.05f) << i;  // sampling noise only
}

TEST(VoronoiCellSums, ALinearFunctionIsRecoveredToTheCellsResolution) {
  // f(w) = w.z: SH (l = 1, m = 0) coefficient sqrt(4 pi / 3); the Voronoi steps of 92 cells
  // blur it a little.
  const std::vector<glm::vec3> dirs = geodesic_directions(3);
  const VoronoiCellSums<3> cells(dirs, 64);
  std::vector<glm::vec3> values;
  for (const glm::vec3& d : dirs) values.push_back(glm::vec3(d.z));
  const sh::CoeffsRgb<3> f = cells.project(values);
  EXPECT_NEAR(f[0][sh::index(1, 0)], std::sqrt(4 * 3.14159265f / 3), 0.03f);
  EXPECT_NEAR(f[0][0], 0.0f, 0.03f);
  EXPECT_THROW(cells.project(std::vector<glm::vec3>(3)), std::invalid_argument);
}

TEST(AlbedoProduct, AConstantAlbedoScalesTheRadiance) {
  sh::CoeffsRgb<4> radiance{};
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < 16; ++i)
      radiance[c][i] = 0.1f * static_cast<float>((i * 7 + c) % 5) - 0.15f;
  }
  sh::CoeffsRgb<4> albedo{};
  albedo[0][0] = 0.5f * kSqrt4Pi, albedo[1][0] = 0.25f * kSqrt4Pi, albedo[2][0] = 0;
  const sh::CoeffsRgb<4> out = albedo_product<4>(radiance, albedo);
  for (int i = 0; i < 16; ++i) {
    EXPECT_NEAR(out[0][i], 0.5f * radiance[0][i], 1e-5f);
    EXPECT_NEAR(out[1][i], 0.25f * radiance[1][i], 1e-5f);
    EXPECT_EQ(out[2][i], 0.0f);
  }
}

}  // namespace
}  // namespace penumbra::spherical_lights
