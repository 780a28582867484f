#include "penumbra/sh/zh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/stability.h"
#include "penumbra/sh/rotation.h"
#include "sh_test_util.h"

namespace penumbra::sh {
namespace {
// Brute force: ZH coefficients of f(cos theta) by a 20000-point midpoint rule in z.
template <int N, class F>
Zonal<N> zh_brute(F f) {
  Zonal<N> z{};
  constexpr int kSteps = 20000;
  for (int s = 0; s < kSteps; ++s) {
    const double x = -1 + (s + 0.5) * 2.0 / kSteps;
    double p[N];
    legendre(x, N, p);
    for (int l = 0; l < N; ++l) {
      z[l] +=
          static_cast<float>(2 * std::numbers::pi * f(x) *
                             std::sqrt((2 * l + 1) / (4 * std::numbers::pi)) * p[l] * 2.0 / kSteps);
    }
  }
  return z;
}

TEST(Zonal, ClampedCosineKnownValues) {
  const auto z = zh_clamped_cosine<5>();
  EXPECT_NEAR(z[0], std::sqrt(kPi) / 2, 1e-6f);
  EXPECT_NEAR(z[1], std::sqrt(kPi / 3), 1e-6f);
  EXPECT_NEAR(z[2], std::sqrt(5 * kPi) / 8, 1e-6f);
  EXPECT_NEAR(z[3], 0.0f, 1e-6f);
  EXPECT_NEAR(z[4], -std::sqrt(kPi) / 16, 1e-6f);
}

TEST(Zonal, CapMatchesBruteForceAndAppendixA1) {
  for (float theta : {0.1f, 0.5f, 1.0f, 1.5708f, 2.5f}) {
    const float t = std::cos(theta);
    const auto z = zh_cap<6>(theta);
    const auto b = zh_brute<6>([&](double x) { return x >= t ? 1.0 : 0.0; });
    for (int l = 0; l < 6; ++l) EXPECT_NEAR(z[l], b[l], 2e-3f) << "theta=" << theta << " l=" << l;
    // [Meier13] eq. A.1, k = 0..3 (k = 3 with (-1 + 5 cos^2)).
    EXPECT_NEAR(z[0], -std::sqrt(kPi) * (-1 + t), 1e-5f);
    EXPECT_NEAR(z[1], 0.5f * std::sqrt(3 * kPi) * std::sin(theta) * std::sin(theta), 1e-5f);
    EXPECT_NEAR(z[2], -0.5f * std::sqrt(5 * kPi) * t * (-1 + t) * (1 + t), 1e-5f);
    EXPECT_NEAR(z[3], -0.125f * std::sqrt(7 * kPi) * (-1 + t) * (1 + t) * (-1 + 5 * t * t), 1e-5f);
  }
}

TEST(Zonal, SphereVisibilityIsOneMinusCapAndLogIsScaledCap) {
  const float r = 1, d = 2;  // half-angle 30 degrees
  const auto v = zh_sphere_visibility<4>(r, d);
  const auto cap = zh_cap<4>(std::asin(0.5f));
  EXPECT_NEAR(v[0], std::sqrt(4 * kPi) - cap[0], 1e-5f);
  for (int l = 1; l < 4; ++l) EXPECT_NEAR(v[l], -cap[l], 1e-6f);
  const auto lv = zh_sphere_log_visibility<4>(r, d, std::log(0.01f));
  for (int l = 0; l < 4; ++l) EXPECT_NEAR(lv[l], std::log(0.01f) * cap[l], 1e-5f);
}

TEST(Zonal, ReceiverInsideBlockerIsFullyOccludedNotNaN) {
  PENUMBRA_STABILITY("a receiver inside a blocker; a zero-size blocker at the receiver",
                     "fully occluded, not NaN; finite", "-");
  const auto v = zh_sphere_visibility<4>(2, 1);
  const auto lv = zh_sphere_log_visibility<4>(2, 1, -4.0f);
  for (int l = 0; l < 4; ++l) EXPECT_EQ(v[l], 0.0f);
  EXPECT_NEAR(lv[0], -4.0f * std::sqrt(4 * kPi), 1e-5f);
  const auto zero = zh_sphere_visibility<4>(0, 0);  // zero-size blocker at the receiver
  for (float c : zero) EXPECT_TRUE(std::isfinite(c));
}

TEST(Zonal, NlpBasisAndLogSliceMatchEquations14And16) {
  const float z = 0.3f;
  const auto p = nlp_basis<4>(z);
  EXPECT_NEAR(p[0], std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(p[1], std::sqrt(3.0f) * z / std::sqrt(2.0f), 1e-6f);
  EXPECT_NEAR(p[2], std::sqrt(5.0f) * std::sqrt(2.0f) * (3 * z * z - 1) / 4, 1e-6f);
  EXPECT_NEAR(p[3], std::sqrt(7.0f) * std::sqrt(2.0f) * (5 * z * z * z - 3 * z) / 4, 1e-6f);
  const float le = std::log(0.05f);
  for (float sigma : {-0.4f, 0.0f, 0.3f, 1.2f}) {
    const auto v = nlp_log_slice<4>(sigma, le);
    const float s = std::sin(sigma), c2 = std::cos(sigma) * std::cos(sigma);
    EXPECT_NEAR(v[0], le * (s + 1) / std::sqrt(2.0f), 1e-5f);
    EXPECT_NEAR(v[1], le * -3 * c2 / (2 * std::sqrt(6.0f)), 1e-5f);
    EXPECT_NEAR(v[2], le * -5 * s * c2 / (2 * std::sqrt(10.0f)), 1e-5f);
    EXPECT_NEAR(v[3], le * 7 * c2 * (-4 + 5 * c2) / (8 * std::sqrt(14.0f)), 1e-5f);
  }
}

TEST(Zonal, RotatedCapMatchesProjectedIndicator) {
  std::mt19937 rng(6);
  const glm::vec3 axis = test::random_direction(rng);
  const float theta = 0.7f;
  const auto sh = rotate_zh<4>(zh_cap<4>(theta), axis);
  const auto brute = project<4>(
      [&](const glm::vec3& d) { return glm::dot(d, axis) >= std::cos(theta) ? 1.0f : 0.0f; },
      test::fine_quadrature());
  EXPECT_LT(test::rel_l2<4>(sh, brute), 5e-3f);
}

}  // namespace
}  // namespace penumbra::sh
