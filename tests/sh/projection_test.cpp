#include "penumbra/sh/projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "common/stability.h"
#include "sh_test_util.h"

namespace penumbra::sh {
namespace {
TEST(Quadrature, WeightsSumToSphereAndIntegratePolynomials) {
  const SphereQuadrature q = SphereQuadrature::gauss(6, 12);
  double sum = 0, z4 = 0, x2y2 = 0;
  for (std::size_t i = 0; i < q.directions.size(); ++i) {
    const glm::vec3 d = q.directions[i];
    sum += q.weights[i];
    z4 += q.weights[i] * std::pow(d.z, 4.0f);
    x2y2 += q.weights[i] * d.x * d.x * d.y * d.y;
  }
  EXPECT_NEAR(sum, 4 * kPi, 1e-4);
  EXPECT_NEAR(z4, 4 * kPi / 5, 1e-4);     // integral of z^4 over the sphere
  EXPECT_NEAR(x2y2, 4 * kPi / 15, 1e-4);  // integral of x^2 y^2
}

TEST(Projection, RecoversBandLimitedFunctions) {
  std::mt19937 rng(3);
  const auto f = test::random_coeffs<5>(rng);
  const auto g = project<5>([&](const glm::vec3& d) { return evaluate<5>(f, d); },
                            SphereQuadrature::gauss(5, 10));
  EXPECT_LT(test::rel_l2<5>(g, f), 1e-5f);
}

TEST(Equirect, DirectionAndUvAreInverse) {
  std::mt19937 rng(4);
  for (int i = 0; i < 100; ++i) {
    const glm::vec3 d = test::random_direction(rng);
    const glm::vec2 uv = equirect_uv(d);
    const glm::vec3 back = equirect_direction(uv.x, uv.y);
    EXPECT_NEAR(back.x, d.x, 1e-5f);
    EXPECT_NEAR(back.y, d.y, 1e-5f);
    EXPECT_NEAR(back.z, d.z, 1e-5f);
  }
  EXPECT_NEAR(equirect_direction(0.3f, 0.0f).z, 1.0f, 1e-6f) << "row 0 is the zenith";
}

TEST(Equirect, TexelSolidAnglesCoverTheSphere) {
  double sum = 0;
  for (int y = 0; y < 64; ++y) sum += 128.0 * equirect_texel_solid_angle(y, 128, 64);
  EXPECT_NEAR(sum, 4 * std::numbers::pi, 1e-5);
}

TEST(Equirect, ProjectionRecoversSmoothMap) {
  std::mt19937 rng(5);
  const auto f = test::random_coeffs<4>(rng);
  const int w = 512, h = 256;
  std::vector<float> rgb(3 * w * h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float v = evaluate<4>(f, equirect_direction((x + 0.5f) / w, (y + 0.5f) / h));
      for (int c = 0; c < 3; ++c) rgb[3 * (y * w + x) + c] = v * (c + 1);
    }
  }
  const auto p = project_equirect<4>(rgb.data(), w, h);
  // Midpoint rule over texels: error O(texel size^2); 512x256 keeps it below 1e-3.
  for (int c = 0; c < 3; ++c) {
    Coeffs<4> expected = f;
    for (float& e : expected) e *= static_cast<float>(c + 1);
    EXPECT_LT(test::rel_l2<4>(p[c], expected), 1e-3f) << "channel " << c;
  }
}

TEST(Equirect, ConstantMapHasOnlyDc) {
  std::vector<float> rgb(3 * 64 * 32, 2.0f);
  const auto p = project_equirect<3>(rgb.data(), 64, 32);
  EXPECT_NEAR(p[0][0], 2.0f * std::sqrt(4 * kPi), 1e-4f);
  // Basis values at texel centres (midpoint rule in theta): O(1e-3) leakage into band 2.
  for (int i = 1; i < 9; ++i) EXPECT_NEAR(p[1][i], 0.0f, 2e-3f * p[1][0]);
}

TEST(Equirect, RejectsEmptyMap) {
  PENUMBRA_STABILITY("an empty equirectangular map", "std::invalid_argument", "-");
  EXPECT_THROW(project_equirect<4>(nullptr, 0, 10), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::sh
