// Wedge tables ([Meier13] eq. 4.15-4.19, 4.26): wedge_exact against closed
// forms and a brute-force projection, the table against wedge_exact, visibility() against the
// plain sum of rotated wedges and against analytic horizons.
#include "penumbra/systems/terrain_shadow/wedge_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"

#include "common/stability.h"
#include "sweep_lanes.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

using test::max_abs_diff;
using test::random_horizon;

template <int N>
sh::Coeffs<N> add(const sh::Coeffs<N>& a, const sh::Coeffs<N>& b) {
  sh::Coeffs<N> s;
  for (int i = 0; i < N * N; ++i) s[i] = a[i] + b[i];
  return s;
}

// Eq. 4.19 written out: sum of the looked-up wedges rotated to phi_k.
template <int N>
sh::Coeffs<N> plain_sum(const WedgeTable<N>& t, const std::vector<float>& a) {
  const int n = t.azimuths();
  sh::Coeffs<N> s{};
  for (int k = 0; k < n; ++k) {
    s = add<N>(s, sh::rotate_z<N>(t.wedge(a[k], a[(k + 1) % n]), 2 * kPi * k / n));
  }
  return s;
}

// Visible above max(w(phi), floor) with w the piecewise-linear horizon through the angles.
float brute_visible(const glm::vec3& d, const std::vector<float>& a, float floor) {
  const int n = static_cast<int>(a.size());
  float phi = std::atan2(d.y, d.x);
  if (phi < 0) phi += 2 * kPi;
  const float u = phi / (2 * kPi / n);
  const int k = std::min(static_cast<int>(u), n - 1);
  const float t = u - k;
  const float w = std::max((1 - t) * a[k] + t * a[(k + 1) % n], floor);
  return std::asin(std::clamp(d.z, -1.0f, 1.0f)) > w ? 1.0f : 0.0f;
}

const sh::SphereQuadrature& brute_quadrature() {
  static const sh::SphereQuadrature q = sh::SphereQuadrature::gauss(256, 2048);
  return q;
}

const WedgeTable<4>& hemisphere32() {
  static const WedgeTable<4> t(32, WedgeDomain::kHemisphere);
  return t;
}
const WedgeTable<4>& sphere32() {
  static const WedgeTable<4> t(32, WedgeDomain::kSphere);
  return t;
}

TEST(WedgeExact, ConstantHorizonSumsToTheCap) {
  // A constant horizon w is the cap of half-angle pi/2 - w about +z (closed form, appendix
  // A.1): tests the elevation quadrature and the azimuth integral, also for wide wedges.
  for (WedgeDomain domain : {WedgeDomain::kHemisphere, WedgeDomain::kSphere}) {
    for (int n : {3, 8, 32}) {
      for (float w : {-1.2f, -0.3f, 0.0f, 0.4f, 1.3f}) {
        const float dphi = 2 * kPi / n;
        sh::Coeffs<4> sum{};
        const sh::Coeffs<4> wedge = wedge_exact<4>(w, w, dphi, domain);
        for (int k = 0; k < n; ++k) sum = add<4>(sum, sh::rotate_z<4>(wedge, dphi * k));
        const float top = domain == WedgeDomain::kHemisphere ? std::max(w, 0.0f) : w;
        const auto cap = sh::zonal_to_sh<4>(sh::zh_cap<4>(kPi / 2 - top));
        EXPECT_LT(max_abs_diff<4>(sum, cap), 5e-6f) << "n " << n << " w " << w;
      }
    }
  }
}

TEST(WedgeExact, IsAdditiveUnderSplitting) {
  // The horizon is linear in phi (eq. 4.15): splitting a wedge at its middle azimuth, with the
  // middle angle as the shared border, gives the same projection (to float precision).
  for (WedgeDomain domain : {WedgeDomain::kHemisphere, WedgeDomain::kSphere}) {
    for (auto [wl, wr] : {std::pair{0.1f, 0.9f}, std::pair{-0.6f, 0.5f}, std::pair{1.2f, -1.0f}}) {
      const float dphi = 2 * kPi / 6, wm = 0.5f * (wl + wr);
      const auto whole = wedge_exact<4>(wl, wr, dphi, domain);
      const auto halves =
          add<4>(wedge_exact<4>(wl, wm, dphi / 2, domain),
                 sh::rotate_z<4>(wedge_exact<4>(wm, wr, dphi / 2, domain), dphi / 2));
      EXPECT_LT(max_abs_diff<4>(whole, halves), 1e-6f) << wl << " " << wr;
    }
  }
}

TEST(WedgeExact, MatchesBruteForceProjection) {
  // Sloped wedges, one crossing 0 on the hemisphere (the max(w, 0) kink), against a direct
  // projection of the indicator (measured 2e-5: the brute force's own error at the edges).
  struct Case {
    float wl, wr;
    WedgeDomain domain;
  };
  for (const Case& c :
       {Case{0.1f, 0.9f, WedgeDomain::kHemisphere}, Case{-0.4f, 0.5f, WedgeDomain::kHemisphere},
        Case{-1.1f, 0.3f, WedgeDomain::kSphere}}) {
    const int n = 8;
    const float dphi = 2 * kPi / n, floor = c.domain == WedgeDomain::kHemisphere ? 0 : -kPi / 2;
    std::vector<float> a(n, kPi / 2);  // only wedge 0 is open
    a[0] = c.wl;
    a[1] = c.wr;
    const auto brute = sh::project<4>(
        [&](const glm::vec3& d) {
          float phi = std::atan2(d.y, d.x);
          if (phi < 0) phi += 2 * kPi;
          return phi < dphi ? brute_visible(d, a, floor) : 0.0f;
        },
        brute_quadrature());
    EXPECT_LT(max_abs_diff<4>(wedge_exact<4>(c.wl, c.wr, dphi, c.domain), brute), 1e-4f)
        << c.wl << " " << c.wr;
  }
}

TEST(WedgeExact, ClosedWedgeIsZeroAndRejectsBadWidth) {
  PENUMBRA_STABILITY("a closed wedge (both horizons at the zenith); width 0 or > 2 pi",
                     "zero; bad widths std::invalid_argument", "-");
  for (WedgeDomain domain : {WedgeDomain::kHemisphere, WedgeDomain::kSphere}) {
    EXPECT_LT(max_abs_diff<4>(wedge_exact<4>(kPi / 2, kPi / 2, 0.3f, domain), {}), 1e-7f);
  }
  EXPECT_THROW(wedge_exact<4>(0, 0, 0, WedgeDomain::kSphere), std::invalid_argument);
  EXPECT_THROW(wedge_exact<4>(0, 0, 7, WedgeDomain::kSphere), std::invalid_argument);
}

TEST(WedgeTable, RejectsBadArguments) {
  PENUMBRA_STABILITY("a wedge table of fewer than 3 azimuths or 1 entry", "std::invalid_argument",
                     "-");
  EXPECT_THROW(WedgeTable<4>(2, WedgeDomain::kSphere), std::invalid_argument);
  EXPECT_THROW(WedgeTable<4>(8, WedgeDomain::kSphere, 1), std::invalid_argument);
}

TEST(WedgeTable, EntriesMatchExactAtAndBetweenNodes) {
  // At nodes the table is wedge_exact (1e-6). Between nodes bilinear interpolation is off by
  // at most 3e-5 on the hemisphere and 1.2e-4 on the sphere (64 x 64, 32 azimuths; measured
  // 1.5e-5 and 6.0e-5 at cell centres, the worst place, over all cells).
  for (const WedgeTable<4>* t : {&hemisphere32(), &sphere32()}) {
    const bool hemi = t->domain() == WedgeDomain::kHemisphere;
    const float lo = hemi ? 0 : -kPi / 2, step = (kPi / 2 - lo) / (t->resolution() - 1);
    const float dphi = 2 * kPi / t->azimuths();
    float at_nodes = 0, between = 0;
    for (int a = 0; a < t->resolution(); a += 3) {
      for (int b = 0; b < t->resolution(); b += 5) {
        const float wl = lo + a * step, wr = lo + b * step;
        at_nodes = std::max(
            at_nodes, max_abs_diff<4>(t->wedge(wl, wr), wedge_exact<4>(wl, wr, dphi, t->domain())));
        if (a + 1 < t->resolution() && b + 1 < t->resolution()) {
          const float ml = wl + step / 2, mr = wr + step / 2;
          between = std::max(between, max_abs_diff<4>(t->wedge(ml, mr),
                                                      wedge_exact<4>(ml, mr, dphi, t->domain())));
        }
      }
    }
    EXPECT_LT(at_nodes, 1e-6f);
    EXPECT_LT(between, hemi ? 3e-5f : 1.2e-4f);
    RecordProperty(hemi ? "hemisphere_between_nodes" : "sphere_between_nodes",
                   std::to_string(between));
  }
}

TEST(WedgeTable, ClampsAnglesToTheDomain) {
  const WedgeTable<4>& h = hemisphere32();
  EXPECT_EQ(h.wedge(-0.5f, 2.0f), h.wedge(0, kPi / 2));
  const WedgeTable<4>& s = sphere32();
  EXPECT_EQ(s.wedge(-3.0f, 0.2f), s.wedge(-kPi / 2, 0.2f));
}

TEST(WedgeTable, VisibilityIsTheSumOfRotatedWedges) {
  // The factored loop (canonical-frame accumulation, one permutation per texel) against
  // eq. 4.19 evaluated literally, for every supported band count.
  std::mt19937 rng(7);
  auto check = [&]<int N>(const WedgeTable<N>& t) {
    for (int trial = 0; trial < 4; ++trial) {
      const auto a = random_horizon(rng, t.azimuths(), -1.7f, 1.7f);
      EXPECT_LT(max_abs_diff<N>(t.visibility(a.data()), plain_sum<N>(t, a)), 2e-5f) << N;
    }
  };
  check(hemisphere32());
  check(sphere32());
  check(WedgeTable<2>(5, WedgeDomain::kSphere, 8));
  check(WedgeTable<3>(7, WedgeDomain::kHemisphere, 8));
  check(WedgeTable<5>(16, WedgeDomain::kSphere, 8));
  check(WedgeTable<6>(9, WedgeDomain::kHemisphere, 8));
  check(WedgeTable<4>(70, WedgeDomain::kSphere, 8));  // two chunks of angles, scalar tail
}

TEST(WedgeTable, OpenAndClosedHorizons) {
  std::vector<float> a(32, 0.0f);
  // Hemisphere, horizon 0: the projection of the upper hemisphere indicator.
  EXPECT_LT(max_abs_diff<4>(hemisphere32().visibility(a.data()),
                            sh::zonal_to_sh<4>(sh::zh_cap<4>(kPi / 2))),
            1e-5f);
  // Sphere, nothing in range (-pi/2): the constant 1, DC sqrt(4 pi) only.
  std::fill(a.begin(), a.end(), -kPi / 2);
  sh::Coeffs<4> one{};
  one[0] = std::sqrt(4 * kPi);
  EXPECT_LT(max_abs_diff<4>(sphere32().visibility(a.data()), one), 1e-5f);
  // Zenith horizons close everything.
  std::fill(a.begin(), a.end(), kPi / 2);
  EXPECT_LT(max_abs_diff<4>(hemisphere32().visibility(a.data()), {}), 1e-6f);
  EXPECT_LT(max_abs_diff<4>(sphere32().visibility(a.data()), {}), 1e-6f);
}

TEST(WedgeTable, ConstantHorizonIsACap) {
  // Exact but for the table's interpolation (w is chosen off the nodes): a cap of half-angle
  // pi/2 - w about +z; 32 wedges add up their interpolation errors in the m = 0 terms
  // (measured up to 3.6e-4 on the hemisphere, 1.2e-3 on the sphere).
  for (const WedgeTable<4>* t : {&hemisphere32(), &sphere32()}) {
    for (float w : {0.013f, 0.37f, 0.81f, 1.234f}) {
      const float ws = t->domain() == WedgeDomain::kSphere ? w - 0.9f : w;
      const std::vector<float> a(32, ws);
      const auto cap = sh::zonal_to_sh<4>(sh::zh_cap<4>(kPi / 2 - ws));
      EXPECT_LT(max_abs_diff<4>(t->visibility(a.data()), cap),
                t->domain() == WedgeDomain::kSphere ? 2e-3f : 6e-4f)
          << ws;
    }
  }
}

TEST(WedgeTable, ShiftingByOneAzimuthRotatesAboutZ) {
  std::mt19937 rng(11);
  for (const WedgeTable<4>* t : {&hemisphere32(), &sphere32()}) {
    const int n = t->azimuths();
    const auto a = random_horizon(rng, n, -0.5f, 1.2f);
    std::vector<float> shifted(n);
    for (int k = 0; k < n; ++k) shifted[(k + 1) % n] = a[k];
    const auto rotated = sh::rotate_z<4>(t->visibility(a.data()), 2 * kPi / n);
    EXPECT_LT(max_abs_diff<4>(t->visibility(shifted.data()), rotated), 1e-5f);
  }
}

TEST(WedgeTable, MatchesBruteForceOfAPiecewiseLinearHorizon) {
  // Whole pipeline against the projected indicator of the interpolated horizon (eq. 4.15,
  // 4.17): table interpolation summed over 32 wedges plus the brute force's own error
  // (measured 6.6e-4 and 4.4e-4).
  std::mt19937 rng(3);
  for (const WedgeTable<4>* t : {&hemisphere32(), &sphere32()}) {
    const bool hemi = t->domain() == WedgeDomain::kHemisphere;
    const auto a = random_horizon(rng, 32, hemi ? 0.0f : -1.2f, 1.0f);
    const auto brute =
        sh::project<4>([&](const glm::vec3& d) { return brute_visible(d, a, hemi ? 0 : -kPi / 2); },
                       brute_quadrature());
    EXPECT_LT(max_abs_diff<4>(t->visibility(a.data()), brute), 1.5e-3f);
  }
}

// The AVX-512 loop (wedge_sum_avx512.cpp: two blocks a vector, an odd last block on 8 lanes)
// gives the 8-lane loop's floats, bit for bit, at every node size (N = 2..7: 1 to 7 blocks),
// with 70 azimuths (a second chunk of 6) and NaN, clamped and in-range angles.
template <int N>
void expect_avx512_bits(std::mt19937& rng, int& compared) {
  const WedgeTable<N> t(70, N % 2 ? WedgeDomain::kSphere : WedgeDomain::kHemisphere, 16);
  for (int trial = 0; trial < 20; ++trial) {
    auto a = random_horizon(rng, 70, -2.0f, 2.0f);
    if (trial % 4 == 0) a[trial % 70] = std::numeric_limits<float>::quiet_NaN();
    detail::force_sweep_isa(detail::SweepIsa::kAvx2);
    const sh::Coeffs<N> avx2 = t.visibility(a.data());
    detail::force_sweep_isa(detail::SweepIsa::kAvx512);
    const sh::Coeffs<N> avx512 = t.visibility(a.data());
    detail::force_sweep_isa(std::nullopt);
    for (int i = 0; i < N * N; ++i)
      ASSERT_EQ(std::memcmp(&avx2[i], &avx512[i], sizeof(float)), 0)
          << "N " << N << " trial " << trial << " coefficient " << i << ": " << avx2[i] << " vs "
          << avx512[i];
    compared += N * N;
  }
}

TEST(WedgeTable, TheAvx512LoopGivesTheEightLaneLoopsBits) {
  if (detail::sweep_isa() != detail::SweepIsa::kAvx512)
    GTEST_SKIP() << "this CPU has no AVX-512: only the 8-lane loop can run";
  std::mt19937 rng(19);
  int compared = 0;
  expect_avx512_bits<2>(rng, compared);
  expect_avx512_bits<3>(rng, compared);
  expect_avx512_bits<4>(rng, compared);
  expect_avx512_bits<5>(rng, compared);
  expect_avx512_bits<6>(rng, compared);
  expect_avx512_bits<7>(rng, compared);
  EXPECT_EQ(compared, 20 * (4 + 9 + 16 + 25 + 36 + 49));
}

}  // namespace
}  // namespace penumbra::terrain_shadow
