#include "penumbra/reference/sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include "common/stability.h"

namespace penumbra::reference {
namespace {

TEST(Pcg32, SameSeedAndStreamRepeatDifferentOnesDiffer) {
  Pcg32 a(7, 3), b(7, 3), c(7, 4), d(8, 3), e(7, 3, 1);
  std::set<std::uint32_t> firsts;
  for (int i = 0; i < 100; ++i) {
    const std::uint32_t x = a.next_u32();
    EXPECT_EQ(x, b.next_u32());
    firsts.insert(x);
  }
  EXPECT_GT(firsts.size(), 95u);
  Pcg32 a2(7, 3);
  int same_c = 0, same_d = 0, same_e = 0;
  for (int i = 0; i < 100; ++i) {
    const std::uint32_t x = a2.next_u32();
    same_c += x == c.next_u32();
    same_d += x == d.next_u32();
    same_e += x == e.next_u32();
  }
  EXPECT_LT(same_c + same_d + same_e, 3);
}

TEST(Pcg32, UniformsInUnitIntervalWithCorrectMoments) {
  Pcg32 rng(1, 2);
  double s = 0, s2 = 0;
  constexpr int kN = 200000;
  for (int i = 0; i < kN; ++i) {
    const double f = rng.next_float(), d = rng.next_double();
    ASSERT_GE(f, 0.0);
    ASSERT_LT(f, 1.0);
    ASSERT_GE(d, 0.0);
    ASSERT_LT(d, 1.0);
    s += d;
    s2 += d * d;
  }
  EXPECT_NEAR(s / kN, 0.5, 4 * std::sqrt(1.0 / 12 / kN));
  EXPECT_NEAR(s2 / kN, 1.0 / 3, 0.003);
}

TEST(StrataGrid, CountsRoundDownToAGrid) {
  EXPECT_EQ(StrataGrid::for_count(64, true).count(), 64);
  EXPECT_EQ(StrataGrid::for_count(64, true).nx, 8);
  EXPECT_EQ(StrataGrid::for_count(10, true).count(), 10);  // 2 x 5
  EXPECT_EQ(StrataGrid::for_count(128, true).nx, 8);       // 8 x 16
  EXPECT_EQ(StrataGrid::for_count(7, true).count(), 6);    // 1 x 7 is too thin: 2 x 3
  EXPECT_EQ(StrataGrid::for_count(127, true).count(), 121);
  EXPECT_EQ(StrataGrid::for_count(12, true).count(), 12);  // 3 x 4
  EXPECT_EQ(StrataGrid::for_count(1, true).count(), 1);
  EXPECT_EQ(StrataGrid::for_count(0, true).count(), 1);
  for (int n = 1; n < 2000; ++n) {
    const StrataGrid g = StrataGrid::for_count(n, true);
    ASSERT_LE(g.count(), n);
    ASSERT_GE(g.count(), n - static_cast<int>(std::sqrt(n)));  // at most a column short
    ASSERT_LE(g.ny, 4 * g.nx);
  }
}

TEST(StrataGrid, PointsStayInTheirStratum) {
  const StrataGrid g = StrataGrid::for_count(12, true);
  Pcg32 rng(3, 0);
  for (int rep = 0; rep < 100; ++rep) {
    for (int h = 0; h < g.count(); ++h) {
      const glm::dvec2 p = g.point(h, rng);
      EXPECT_EQ(static_cast<int>(p.x * g.nx), h % g.nx);
      EXPECT_EQ(static_cast<int>(p.y * g.ny), h / g.nx);
    }
  }
  const glm::vec2 f = to_float({0x1.fffffffffffffp-1, 0.25});
  EXPECT_LT(f.x, 1.0f);
  EXPECT_EQ(f.y, 0.25f);
}

TEST(Warps, CosineHemisphereIsUnitUpperWithMeanCosTwoThirds) {
  Pcg32 rng(5, 0);
  double mean_z = 0;
  constexpr int kN = 100000;
  for (int i = 0; i < kN; ++i) {
    const glm::vec3 w = cosine_hemisphere({rng.next_float(), rng.next_float()});
    ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
    ASSERT_GE(w.z, 0.0f);
    mean_z += w.z;
  }
  // E[cos] under density cos/pi = (1/pi) int cos^2 = 2/3; var = 1/2 - 4/9.
  EXPECT_NEAR(mean_z / kN, 2.0 / 3, 4 * std::sqrt((0.5 - 4.0 / 9) / kN));
}

TEST(Warps, SphereAndHemisphereAreUniform) {
  Pcg32 rng(6, 0);
  constexpr int kN = 100000;
  double z_sphere = 0, z_hemi = 0, x_sphere = 0;
  for (int i = 0; i < kN; ++i) {
    const glm::vec3 a = uniform_sphere({rng.next_float(), rng.next_float()});
    const glm::vec3 b = uniform_hemisphere({rng.next_float(), rng.next_float()});
    ASSERT_NEAR(glm::length(a), 1.0f, 1e-5f);
    ASSERT_NEAR(glm::length(b), 1.0f, 1e-5f);
    ASSERT_GE(b.z, 0.0f);
    z_sphere += a.z;
    x_sphere += a.x;
    z_hemi += b.z;
  }
  const double tol = 4 * std::sqrt(1.0 / 3 / kN);
  EXPECT_NEAR(z_sphere / kN, 0, tol);
  EXPECT_NEAR(x_sphere / kN, 0, tol);
  EXPECT_NEAR(z_hemi / kN, 0.5, tol);
}

TEST(Warps, ConeStaysInsideItsCapEvenWhenTiny) {
  PENUMBRA_STABILITY("a cone of tiny angle", "samples stay inside the cap and reach its rim", "-");
  Pcg32 rng(7, 0);
  for (double sin_a : {0.9, 0.1, 1e-3, 1e-5}) {
    const double cos_a = std::sqrt(1 - sin_a * sin_a), omc = sin_a * sin_a / (1 + cos_a);
    double max_sin = 0;
    for (int i = 0; i < 10000; ++i) {
      const glm::vec3 w = uniform_cone({rng.next_float(), rng.next_float()}, omc);
      ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
      max_sin = std::max(max_sin, std::hypot(double(w.x), double(w.y)));
    }
    EXPECT_LE(max_sin, sin_a * (1 + 1e-5));
    EXPECT_GT(max_sin, sin_a * 0.95);  // the samples reach the rim, not a smaller cone
  }
}

TEST(Frame, IsOrthonormalForAnyNormal) {
  Pcg32 rng(8, 0);
  for (int i = 0; i < 1000; ++i) {
    glm::vec3 n = uniform_sphere({rng.next_float(), rng.next_float()});
    if (i == 0) n = {0, 0, -1};
    if (i == 1) n = {0, 0, 1};
    const Frame f(n);
    EXPECT_NEAR(glm::dot(f.t, f.b), 0, 1e-5f);
    EXPECT_NEAR(glm::dot(f.t, f.n), 0, 1e-5f);
    EXPECT_NEAR(glm::dot(f.b, f.n), 0, 1e-5f);
    EXPECT_NEAR(glm::length(f.t), 1, 1e-5f);
    EXPECT_NEAR(glm::length(f.b), 1, 1e-5f);
    EXPECT_NEAR(glm::dot(f.to_world({0, 0, 1}), n), 1, 1e-5f);
  }
}

TEST(PairedMean, MeanAndStandardErrorFromPairs) {
  PairedMean<1> m;
  m.add_pair({1.0}, {3.0});
  m.add_pair({2.0}, {2.0});
  EXPECT_DOUBLE_EQ(m.mean(0), 2.0);
  // (1/H^2) sum (a - b)^2 / 4 = (1/4) * (4 + 0) / 4 = 0.25.
  EXPECT_DOUBLE_EQ(m.std_error(0), 0.5);
  EXPECT_EQ(m.pairs(), 2u);
  EXPECT_EQ(m.differing_pairs(0), 1u);
  EXPECT_EQ(m.dof(), 1u);
  PairedMean<2> two;  // channel 1 never varies: dof comes from channel 0 only
  two.add_pair({1.0, 5.0}, {2.0, 5.0});
  two.add_pair({1.0, 5.0}, {3.0, 5.0});
  EXPECT_EQ(two.dof(), 2u);
  EXPECT_EQ(two.std_error(1), 0.0);
  PairedMean<1> empty;
  EXPECT_EQ(empty.mean(0), 0.0);
  EXPECT_EQ(empty.std_error(0), 0.0);
}

// The error bar is calibrated: over many independent stratified estimates of a discontinuous
// 2D integral (the area of a disk, pi / 4 of the square), mean (z^2) is close to 1.
// (With few strata on the boundary the error bar has few degrees of freedom and z is Student-t
// distributed, E z^2 = dof / (dof - 2): 256 strata put about 30 on the circle.)
TEST(PairedMean, StratifiedErrorBarsAreCalibrated) {
  const StrataGrid g = StrataGrid::for_count(256, true);
  double z2 = 0;
  constexpr int kTrials = 1000;
  for (int t = 0; t < kTrials; ++t) {
    Pcg32 rng(11, t);
    PairedMean<1> m;
    for (int h = 0; h < g.count(); ++h) {
      const glm::dvec2 a = g.point(h, rng), b = g.point(h, rng);
      m.add_pair({a.x * a.x + a.y * a.y < 1 ? 1.0 : 0.0}, {b.x * b.x + b.y * b.y < 1 ? 1.0 : 0.0});
    }
    if (m.std_error(0) > 0) {
      const double z = (m.mean(0) - std::numbers::pi / 4) / m.std_error(0);
      z2 += z * z;
    }
  }
  EXPECT_GT(z2 / kTrials, 0.8);
  EXPECT_LT(z2 / kTrials, 1.35);
}

}  // namespace
}  // namespace penumbra::reference
