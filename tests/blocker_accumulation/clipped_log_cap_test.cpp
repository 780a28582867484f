#include "penumbra/systems/blocker_accumulation/clipped_log_cap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "common/stability.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/rotation.h"
#include "test_skies.h"

namespace penumbra::blocker_accumulation {
namespace {

// The cap's band-limited visibility 1 - cap about +z.
sh::Coeffs<N> cap_visibility(float sin_angle) {
  const sh::Zonal<N> cap = sh::zh_cap<N>(std::asin(sin_angle));
  sh::Coeffs<N> v{};
  v[0] = std::sqrt(4 * std::numbers::pi_v<float>) - cap[0];
  for (int l = 1; l < N; ++l) v[sh::index(l, 0)] = -cap[l];
  return v;
}

float rel_l2(const sh::Coeffs<N>& a, const sh::Coeffs<N>& b) {
  float num = 0, den = 0;
  for (int i = 0; i < N * N; ++i) {
    num += (a[i] - b[i]) * (a[i] - b[i]);
    den += b[i] * b[i];
  }
  return std::sqrt(num / den);
}

TEST(ClippedLogCap, NoCapHasZeroLog) {
  PENUMBRA_STABILITY("a cap of angle 0 (no blocker)", "zero log visibility in every band", "-");
  const sh::Zonal<N> z = ClippedLogCap<N>::compute(0.0f, 0.02f);
  for (int l = 0; l < N; ++l) EXPECT_NEAR(z[l], 0.0f, 1e-5f) << "band " << l;
}

// The point of the log: its exponential gives the visibility back. For caps the clip does not
// touch (M_v well conditioned) exactly; for wide caps up to what the clipped eigenvalues lose.
TEST(ClippedLogCap, ExponentialGivesTheVisibilityBack) {
  const ClippedLogCap<N> table;
  std::printf("sin  rel L2 |exp(log v) - v| / |v|  (log at the axis)\n");
  for (const float s : {0.1f, 0.3f, 0.5f, 0.7f, 0.9f}) {
    const sh::Coeffs<N> log_v = sh::zonal_to_sh<N>(table.log_zh(s));
    const float err = rel_l2(sh::exp_numeric<N>(log_v), cap_visibility(s));
    std::printf("%.1f  %.4f  (%.3f)\n", s, err, sh::evaluate<N>(log_v, {0, 0, 1}));
    EXPECT_LT(err, s <= 0.5f ? 0.02f : 0.15f) << "sin " << s;
  }
}

TEST(ClippedLogCap, TableInterpolatesTheExactLog) {
  const ClippedLogCap<N> table;
  for (const float s : {0.013f, 0.25f, 0.4999f, 0.77f, 0.999f}) {
    const sh::Zonal<N> exact = ClippedLogCap<N>::compute(s, 0.02f);
    const sh::Zonal<N> lerp = table.log_zh(s);
    for (int l = 0; l < N; ++l)
      EXPECT_NEAR(lerp[l], exact[l], 0.01f) << "sin " << s << " band " << l;
  }
}

TEST(ClippedLogCap, TighterClipGoesDeeper) {
  const float d2 = ClippedLogCap<N>(0.02f, 3).depth();
  const float d5 = ClippedLogCap<N>(0.005f, 3).depth();
  EXPECT_LT(d2, 0.0f);
  EXPECT_LT(d5, d2);
}

TEST(ClippedLogCap, RotatedLikeTheCap) {
  const ClippedLogCap<N> table;
  const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  sh::Coeffs<N> sum{};
  add_log_visibility<N>(BlockerView{axis, 0.4f, 0.5f}, table, sum);
  const sh::Coeffs<N> expected = sh::rotate_zh<N>(table.log_zh(0.4f), axis);
  for (int i = 0; i < N * N; ++i) EXPECT_NEAR(sum[i], 0.5f * expected[i], 1e-5f) << i;
}

TEST(ClippedLogCap, RejectsBadSettings) {
  PENUMBRA_STABILITY("epsilon 0, 1 or NaN; a table of 1 entry", "std::invalid_argument", "-");
  EXPECT_THROW(ClippedLogCap<N>(0.0f), std::invalid_argument);
  EXPECT_THROW(ClippedLogCap<N>(1.0f), std::invalid_argument);
  EXPECT_THROW(ClippedLogCap<N>(std::nanf("")), std::invalid_argument);
  EXPECT_THROW(ClippedLogCap<N>(0.02f, 1), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
