#include "penumbra/sh/convolution.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/stability.h"
#include "penumbra/sh/rotation.h"
#include "sh_test_util.h"

namespace penumbra::sh {
namespace {
TEST(Irradiance, ConstantSkyGivesPiL) {
  Coeffs<4> l{};
  l[0] = 2.0f * std::sqrt(4 * kPi);  // L = 2 everywhere
  const auto e = irradiance_convolve<4>(l);
  std::mt19937 rng(30);
  for (int t = 0; t < 20; ++t)
    EXPECT_NEAR(evaluate<4>(e, test::random_direction(rng)), 2 * kPi, 1e-4f);
}

TEST(Irradiance, MatchesBruteForceCosineIntegral) {
  std::mt19937 rng(31);
  auto l = test::random_coeffs<3>(rng);
  l[0] += 5;  // mostly positive radiance
  const auto e = irradiance_convolve<3>(l);
  const auto& q = test::fine_quadrature();
  for (int t = 0; t < 5; ++t) {
    const glm::vec3 n = test::random_direction(rng);
    double brute = 0;
    for (std::size_t i = 0; i < q.directions.size(); ++i) {
      brute += evaluate<3>(l, q.directions[i]) * std::fmax(0.0f, glm::dot(n, q.directions[i])) *
               q.weights[i];
    }
    // 3-band radiance: irradiance_convolve is exact; the brute force has the cosine's kink.
    EXPECT_NEAR(evaluate<3>(e, n), brute, 2e-3 * std::abs(brute));
  }
}

TEST(Deringing, SmoothSkyNeedsNoWindow) {
  Coeffs<4> l{};
  l[0] = 3.0f;
  l[2] = 0.5f;
  std::array<float, 4> w;
  const auto e = dering_irradiance<4>(l, &w);
  for (float x : w) EXPECT_EQ(x, 1.0f);
  EXPECT_EQ(e, irradiance_convolve<4>(l));
}

TEST(Deringing, SharpLightGetsAWindowAndNonNegativeIrradiance) {
  PENUMBRA_STABILITY("a bright 3-degree sun over a dim sky at 5 bands",
                     "rings: negative irradiance opposite the sun",
                     "deringing window (the weakest that removes it)");
  // A bright 3-degree sun over a dim sky, projected to 5 bands, rings: its irradiance dips
  // below zero opposite the sun. Deringing must remove that with the weakest window.
  const float sun = 3.0f * kPi / 180;
  Coeffs<5> l = rotate_zh<5>(zh_cap<5>(sun), glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f)));
  for (float& c : l) c *= 20000.0f;
  l[0] += 0.05f * std::sqrt(4 * kPi);
  ASSERT_LT(min_value<5>(irradiance_convolve<5>(l)), 0.0f) << "the test case must ring";
  std::array<float, 5> w;
  const auto e = dering_irradiance<5>(l, &w);
  EXPECT_GE(min_value<5>(e), -1e-4f * e[0] * 0.2820948f);
  EXPECT_LT(w[4], 1.0f);
  EXPECT_EQ(w[0], 1.0f) << "the mean is never changed";
}

}  // namespace
}  // namespace penumbra::sh
