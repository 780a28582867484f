// Log-SH wedges ([Giraud] sec. 4.1, eq. 15-23): M_lin's shape, the whole
// log-visibility against eq. 20 written out and against a brute-force projection of the
// interpolated slices, closed forms for constant horizons, and exp(log V) against the primal
// wedge-table visibility.
#include "penumbra/systems/terrain_shadow/log_wedge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"
#include "penumbra/systems/terrain_shadow/wedge_table.h"

#include "common/stability.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

using test::max_abs_diff;
using test::random_horizon;

constexpr float kLogEps = -3.0f;

template <int N>
float norm(const sh::Coeffs<N>& a) {
  return std::sqrt(sh::dot<N>(a, a));
}

// Eq. 20 literally: sum_k rotate_z(M_lin [v_k; v_k+1], phi_k), v_k = nlp_log_slice.
template <int N>
sh::Coeffs<N> literal(const LogWedge<N>& w, const std::vector<float>& a) {
  const int n = w.azimuths();
  sh::Coeffs<N> sum{};
  for (int k = 0; k < n; ++k) {
    const auto vl = sh::nlp_log_slice<N>(a[k], w.log_eps());
    const auto vr = sh::nlp_log_slice<N>(a[(k + 1) % n], w.log_eps());
    sh::Coeffs<N> wedge{};
    for (int i = 0; i < N * N; ++i) {
      for (int j = 0; j < N; ++j) {
        wedge[i] += w.m_lin()[i * 2 * N + j] * vl[j] + w.m_lin()[i * 2 * N + N + j] * vr[j];
      }
    }
    const auto r = sh::rotate_z<N>(wedge, 2 * kPi * k / n);
    for (int i = 0; i < N * N; ++i) sum[i] += r[i];
  }
  return sum;
}

TEST(LogWedge, ShapeAndArguments) {
  const LogWedge<4> w(32, kLogEps);
  EXPECT_EQ(w.m_lin().size(), 16u * 8u);
  EXPECT_EQ(w.azimuths(), 32);
  EXPECT_EQ(w.log_eps(), kLogEps);
  EXPECT_EQ(LogWedge<3>(8, kLogEps).m_lin().size(), 9u * 6u);
  EXPECT_THROW(LogWedge<4>(2, kLogEps), std::invalid_argument);
  EXPECT_THROW(LogWedge<4>(8, 0.0f), std::invalid_argument);
  EXPECT_THROW(LogWedge<4>(8, 0.5f), std::invalid_argument);
  EXPECT_THROW(LogWedge<4>(8, -INFINITY), std::invalid_argument);
  EXPECT_THROW(LogWedge<4>(8, NAN), std::invalid_argument);
}

TEST(LogWedge, MatchesBruteForceProjection) {
  // The function eq. 19 defines (per wedge, the slices' NLP reconstructions interpolated
  // linearly in phi), projected with a fine quadrature whose azimuth nodes are midpoints of
  // 32 sub-intervals per wedge. Measured 1.7e-5 absolute (|log V| = 5.9) and, against
  // eq. 20 written out, 1e-6.
  std::mt19937 rng(5);
  const int n = 32;
  const LogWedge<4> w(n, kLogEps);
  const auto a = random_horizon(rng, n, -1.4f, 1.4f);
  std::vector<std::array<float, 4>> v(n);
  for (int k = 0; k < n; ++k) v[k] = sh::nlp_log_slice<4>(a[k], kLogEps);
  static const sh::SphereQuadrature q = sh::SphereQuadrature::gauss(48, 32 * n);
  const auto brute = sh::project<4>(
      [&](const glm::vec3& d) {
        float phi = std::atan2(d.y, d.x);
        if (phi < 0) phi += 2 * kPi;
        const float u = phi / (2 * kPi / n);
        const int k = std::min(static_cast<int>(u), n - 1);
        const float alpha = u - k;
        const auto p = sh::nlp_basis<4>(d.z);
        float f = 0;
        for (int j = 0; j < 4; ++j) f += p[j] * ((1 - alpha) * v[k][j] + alpha * v[(k + 1) % n][j]);
        return f;
      },
      q);
  const auto got = w.log_visibility(a.data());
  EXPECT_LT(max_abs_diff<4>(got, brute), 2e-5f * norm<4>(brute));
  // The factored sum (G_k matrices, float slices) against eq. 20 written out.
  EXPECT_LT(max_abs_diff<4>(got, literal<4>(w, a)), 1e-5f * norm<4>(brute));
}

TEST(LogWedge, FactoredSumMatchesEq20ForAllBandCounts) {
  std::mt19937 rng(9);
  auto check = [&]<int N>(const LogWedge<N>& w) {
    const auto a = random_horizon(rng, w.azimuths(), -1.6f, 1.6f);
    const auto ref = literal<N>(w, a);
    EXPECT_LT(max_abs_diff<N>(w.log_visibility(a.data()), ref), 1e-5f * norm<N>(ref)) << N;
  };
  check(LogWedge<2>(5, -2.0f));
  check(LogWedge<3>(13, -4.0f));
  check(LogWedge<4>(32, kLogEps));
  check(LogWedge<5>(17, -1.0f));
  check(LogWedge<6>(40, -6.0f));  // more than one chunk of eight, with a tail
}

TEST(LogWedge, ConstantHorizonIsALogCap) {
  // A constant horizon sigma occludes the cap of half-angle pi/2 + sigma about -z: log_eps
  // times that cap's projection, exactly (the interpolation of equal slices is exact).
  const LogWedge<4> w(32, kLogEps);
  for (float sigma : {-1.2f, -0.4f, 0.0f, 0.3f, 1.1f}) {
    const std::vector<float> a(32, sigma);
    auto cap = sh::zh_cap<4>(kPi / 2 + sigma);
    for (float& c : cap) c *= kLogEps;
    const auto expected = sh::rotate_zh<4>(cap, glm::vec3(0, 0, -1));
    EXPECT_LT(max_abs_diff<4>(w.log_visibility(a.data()), expected), 2e-5f) << sigma;
  }
}

TEST(LogWedge, NoTerrainIsZeroAndShiftRotates) {
  PENUMBRA_STABILITY("no terrain in range (every horizon at -pi/2)",
                     "log visibility zero up to float rounding (1.8e-6 measured)", "-");
  const LogWedge<4> w(32, kLogEps);
  // Nothing in range: zero up to float sin(-pi/2) (measured 1.8e-6; log eps sqrt(4 pi) ~ 10).
  std::vector<float> a(32, -kPi / 2);
  EXPECT_LT(max_abs_diff<4>(w.log_visibility(a.data()), {}), 1e-5f);
  std::mt19937 rng(2);
  a = random_horizon(rng, 32, -1.0f, 1.0f);
  std::vector<float> shifted(32);
  for (int k = 0; k < 32; ++k) shifted[(k + 1) % 32] = a[k];
  const auto rotated = sh::rotate_z<4>(w.log_visibility(a.data()), 2 * kPi / 32);
  EXPECT_LT(max_abs_diff<4>(w.log_visibility(shifted.data()), rotated), 2e-5f);
}

TEST(LogWedge, ExpApproximatesThePrimalVisibility) {
  // A mild horizon (elevations -0.5..0.3, log eps = -3): exp_hyb of the log-SH visibility
  // against the wedge table's primal visibility (sphere domain). They differ by design:
  // eps = e^-3 instead of 0 below the horizon, slices interpolated in log space (eq. 19) rather
  // than the horizon angle, and exp of a 4-band log (even the exact exp_numeric is off by
  // 11-18%, as much for a constant horizon). Measured: relative L2 <= 18%, DC <= 10% low, HYB
  // against exp_numeric <= 7%. Asserted: 25%, 15%, 10%.
  std::mt19937 rng(13);
  const LogWedge<4> w(32, kLogEps);
  const WedgeTable<4> table(32, WedgeDomain::kSphere, 32);
  for (int trial = 0; trial < 5; ++trial) {
    const auto a = random_horizon(rng, 32, -0.5f, 0.3f);
    const auto primal = table.visibility(a.data());
    const auto log_v = w.log_visibility(a.data());
    const auto approx = sh::exp_hyb<4>(log_v), numeric = sh::exp_numeric<4>(log_v);
    sh::Coeffs<4> diff, hyb_error;
    for (int i = 0; i < 16; ++i) {
      diff[i] = approx[i] - primal[i];
      hyb_error[i] = approx[i] - numeric[i];
    }
    EXPECT_LT(norm<4>(diff), 0.25f * norm<4>(primal)) << trial;
    EXPECT_NEAR(approx[0], primal[0], 0.15f * primal[0]) << trial;
    EXPECT_LT(norm<4>(hyb_error), 0.10f * norm<4>(numeric)) << trial;
  }
}

}  // namespace
}  // namespace penumbra::terrain_shadow
