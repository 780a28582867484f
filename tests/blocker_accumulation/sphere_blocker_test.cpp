#include "penumbra/systems/blocker_accumulation/sphere_blocker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "common/stability.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"
#include "test_skies.h"

namespace penumbra::blocker_accumulation {
namespace {

const glm::vec3 kUp{0, 0, 1};

sh::Coeffs<N> log_vis(const glm::vec3& p, const glm::vec3& n, const glm::vec3& c, float r,
                      const SphereBlockerSettings& s = {}) {
  sh::Coeffs<N> sum{};
  add_log_visibility<N>(view_blocker(p, n, c, r, s), std::log(s.epsilon), sum);
  return sum;
}

// Irradiance under a uniform unit sky through the exponentiated visibility: V . cosine lobe.
float sky_irradiance(const sh::Coeffs<N>& log_v, const glm::vec3& n) {
  const sh::Coeffs<N> v = sh::exp_visibility<N>(log_v);
  const sh::Coeffs<N> cosine = sh::rotate_zh<N>(sh::zh_clamped_cosine<N>(), n);
  // A uniform unit radiance projects to (sqrt(4 pi), 0, ...): E = int V max(0, n.w) dw.
  return sh::dot<N>(sh::product<N>(v, cosine), [] {
    sh::Coeffs<N> one{};
    one[0] = std::sqrt(4 * std::numbers::pi_v<float>);
    return one;
  }());
}

TEST(SphereBlocker, FarAboveMatchesTheRotatedAnalyticLogZh) {
  // [Giraud] eq. 26 rotated towards the blocker: the closed form here against zh.h's.
  const glm::vec3 p{1, 2, 0}, c{4, 3, 6};
  const float r = 1.5f, eps = 0.2f;
  const sh::Coeffs<N> ours = log_vis(p, kUp, c, r, {eps, RatioAttenuation::kOff, 0});
  const sh::Coeffs<N> expected = sh::rotate_zh<N>(
      sh::zh_sphere_log_visibility<N>(r, glm::length(c - p), std::log(eps)), glm::normalize(c - p));
  for (int i = 0; i < N * N; ++i) EXPECT_NEAR(ours[i], expected[i], 1e-5f) << i;
}

TEST(SphereBlocker, WhollyBelowThePlaneIsCulledAndWhollyAboveIsUnchanged) {
  EXPECT_EQ(view_blocker({0, 0, 0}, kUp, {3, 0, -2}, 1.5f, {}).weight, 0.0f);  // top at -0.5
  const BlockerView above = view_blocker({0, 0, 0}, kUp, {3, 0, 2}, 1.5f, {});
  EXPECT_FLOAT_EQ(above.weight, 1.0f);
  EXPECT_NEAR(above.sin_angle, 1.5f / std::sqrt(13.0f), 1e-6f);
  const BlockerView cut = view_blocker({0, 0, 0}, kUp, {3, 0, 0}, 1.5f, {});  // half above
  EXPECT_GT(cut.weight, 0.0f);
  EXPECT_LT(cut.weight, 1.0f);
}

TEST(SphereBlocker, DegenerateSpheresAreFinite) {
  PENUMBRA_STABILITY(
      "a sphere of radius 0 or < 0; a sphere centred on the receiver",
      "weight 0; centred: replaced by the upper half's sphere (weight 0.5); all finite", "-");
  EXPECT_EQ(view_blocker({0, 0, 0}, kUp, {0, 0, 3}, 0.0f, {}).weight, 0.0f);  // zero radius
  EXPECT_EQ(view_blocker({0, 0, 0}, kUp, {0, 0, 3}, -1.0f, {}).weight, 0.0f);
  // Centred on the receiver: replaced by the upper half's sphere, touching the receiver.
  const BlockerView centred = view_blocker({0, 0, 0}, kUp, {0, 0, 0}, 2.0f, {});
  EXPECT_FLOAT_EQ(centred.sin_angle, 1.0f);
  EXPECT_NEAR(centred.weight, 0.5f, 1e-6f);
  const sh::Coeffs<N> v = log_vis({0, 0, 0}, kUp, {0, 0, 0}, 2.0f);
  for (float x : v) EXPECT_TRUE(std::isfinite(x));
}

TEST(SphereBlocker, RatioAttenuationScalesBySinOfTheAngularRadius) {
  SphereBlockerSettings on{0.2f, RatioAttenuation::kOn, 0};
  SphereBlockerSettings off{0.2f, RatioAttenuation::kOff, 0};
  const BlockerView a = view_blocker({0, 0, 0}, kUp, {0, 1, 5}, 1.0f, on);
  const BlockerView b = view_blocker({0, 0, 0}, kUp, {0, 1, 5}, 1.0f, off);
  EXPECT_NEAR(a.weight, b.weight * b.sin_angle, 1e-6f);
}

TEST(SphereBlocker, SmallBlockersFadeOutAtTheCutOff) {
  SphereBlockerSettings s;
  s.min_sin = 0.05f;
  EXPECT_EQ(view_blocker({0, 0, 0}, kUp, {0, 0, 100}, 4.0f, s).weight, 0.0f);  // sin 0.04
  EXPECT_FLOAT_EQ(view_blocker({0, 0, 0}, kUp, {0, 0, 10}, 4.0f, s).weight, 1.0f);
  const float w = view_blocker({0, 0, 0}, kUp, {0, 0, 4.0f / 0.075f}, 4.0f, s).weight;
  EXPECT_GT(w, 0.0f);
  EXPECT_LT(w, 1.0f);
}

// A sphere lowered slowly through the receiver's tangent plane, and one slid sideways into the
// receiver at contact height: the irradiance under a uniform sky never jumps between frames.
// Bound: 1% of the unoccluded irradiance (pi) per step of r / 500; the largest measured step is
// printed.
TEST(SphereBlocker, CrossingTheTangentPlaneAndTheReceiverDoesNotPop) {
  const float r = 1.0f;
  const glm::vec3 p{0, 0, 0};
  float worst = 0, prev = -1;
  float lowest = 1e9f, highest = -1e9f;
  for (int i = 0; i <= 2000; ++i) {  // centre height from 2.5 r down to -1.5 r, 0.3 r aside
    const float h = 2.5f * r - 4.0f * r * i / 2000.0f;
    const float e = sky_irradiance(log_vis(p, kUp, {0.3f * r, 0, h}, r), kUp);
    ASSERT_TRUE(std::isfinite(e)) << h;
    if (prev >= 0) worst = std::max(worst, std::abs(e - prev));
    prev = e;
    lowest = std::min(lowest, e);
    highest = std::max(highest, e);
  }
  const float pi = std::numbers::pi_v<float>;
  std::printf("lowering: largest step %.5f (%.3f%% of pi), range %.3f..%.3f\n", worst,
              100 * worst / pi, lowest, highest);
  EXPECT_LT(worst, 0.01f * pi);
  EXPECT_LT(lowest, 0.5f * pi);       // it did shadow on the way
  EXPECT_NEAR(prev, pi, 0.02f * pi);  // and wholly below it is gone (SH ringing aside)

  worst = 0;
  prev = -1;
  for (int i = 0; i <= 2000; ++i) {  // resting on the plane (centre at height r), sliding over p
    const float x = 3.0f * r - 6.0f * r * i / 2000.0f;
    const float e = sky_irradiance(log_vis(p, kUp, {x, 0, r}, r), kUp);
    ASSERT_TRUE(std::isfinite(e)) << x;
    if (prev >= 0) worst = std::max(worst, std::abs(e - prev));
    prev = e;
  }
  std::printf("sliding: largest step %.5f (%.3f%% of pi)\n", worst, 100 * worst / pi);
  EXPECT_LT(worst, 0.01f * pi);
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
