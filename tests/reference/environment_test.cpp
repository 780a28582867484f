#include "penumbra/reference/environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "common/stability.h"
#include "penumbra/reference/sampling.h"
#include "penumbra/sh/projection.h"
#include "reference_test_util.h"

namespace penumbra::reference {
namespace {

using test::make_map;

// A small map with very different texels: luminance varies by 4 orders of magnitude, one
// texel black, one red-only.
data::EnvironmentMap varied_map(int w = 8, int h = 4) {
  return make_map(
      w, h,
      [w](int x, int y) {
        if (x == 2 && y == 1) return glm::vec3(0);
        if (x == 5 && y == 2) return glm::vec3(3, 0, 0);
        const float v = std::pow(10.0f, static_cast<float>((x * 7 + y * 3) % 5) - 2.0f);
        return glm::vec3(v, 0.5f * v + 0.01f * x, 2 * v + 0.001f * w);
      },
      "varied.exr");
}

void expect_throws_naming(const data::EnvironmentMap& m, float rot, const std::string& part) {
  try {
    EnvironmentSampler s(m, rot);
    ADD_FAILURE() << "no exception for " << part;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("varied.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(EnvironmentSampler, RejectsBadMapsNamingThem) {
  PENUMBRA_STABILITY(
      "a map of size 0, too few floats, a negative or NaN texel; an infinite rotation",
      "std::invalid_argument naming the map and the texel", "-");
  auto m = varied_map();
  m.width = 0;
  expect_throws_naming(m, 0, "size");
  m = varied_map();
  m.rgb.pop_back();
  expect_throws_naming(m, 0, "rgb holds");
  m = varied_map();
  m.rgb[3 * 9 + 1] = -1;
  expect_throws_naming(m, 0, "texel (1, 1)");
  m = varied_map();
  m.rgb[0] = std::numeric_limits<float>::quiet_NaN();
  expect_throws_naming(m, 0, "texel (0, 0)");
  expect_throws_naming(varied_map(), std::numeric_limits<float>::infinity(), "rotation");
}

TEST(EnvironmentSampler, BlackMapCannotBeSampledButLooksUp) {
  const EnvironmentSampler s(test::constant_map(16, 8, glm::vec3(0)), 0);
  EXPECT_FALSE(s.can_sample());
  const auto l = s.lookup({0, 0, 1});
  EXPECT_EQ(l.radiance, glm::vec3(0));
  EXPECT_EQ(l.pdf, 0.0f);
}

// sum over texels of pdf x solid angle = 1, and pdf is luminance / integral.
TEST(EnvironmentSampler, DensityIntegratesToOne) {
  const auto m = varied_map(32, 16);
  const EnvironmentSampler s(m, 0.3f);
  double sum = 0;
  for (int y = 0; y < m.height; ++y) {
    for (int x = 0; x < m.width; ++x) {
      const glm::vec3 d = sh::equirect_direction((x + 0.5f) / m.width, (y + 0.5f) / m.height);
      // Rotate the map-frame texel centre into the world frame before the lookup.
      const float c = std::cos(0.3f), sn = std::sin(0.3f);
      const glm::vec3 world{c * d.x - sn * d.y, sn * d.x + c * d.y, d.z};
      const auto l = s.lookup(world);
      const float* t = m.texel(x, y);
      EXPECT_EQ(l.radiance, glm::vec3(t[0], t[1], t[2])) << x << "," << y;
      sum += l.pdf * sh::equirect_texel_solid_angle(y, m.width, m.height);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-5);
}

// Every sample carries the radiance and density of the texel its direction falls in, and its
// direction is unit length.
TEST(EnvironmentSampler, SamplesAgreeWithLookup) {
  const EnvironmentSampler s(varied_map(), -1.1f);
  Pcg32 rng(1, 0);
  int mismatches = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto smp = s.sample({rng.next_double(), rng.next_double()});
    ASSERT_NEAR(glm::length(smp.dir), 1.0f, 1e-5f);
    ASSERT_GT(smp.pdf, 0.0f);
    const auto l = s.lookup(smp.dir);
    mismatches += l.radiance != smp.radiance || l.pdf != smp.pdf;  // only on texel edges
  }
  EXPECT_LE(mismatches, 2);
}

// Texel histogram of many samples matches the texel probabilities (chi-square, 32 texels).
TEST(EnvironmentSampler, SampleHistogramMatchesProbabilities) {
  const auto m = varied_map();
  const EnvironmentSampler s(m, 0);
  std::vector<int> counts(m.width * m.height, 0);
  constexpr int kN = 400000;
  Pcg32 rng(2, 0);
  for (int i = 0; i < kN; ++i) {
    const auto smp = s.sample({rng.next_double(), rng.next_double()});
    const glm::vec2 uv = sh::equirect_uv(smp.dir);
    const int x = std::min(static_cast<int>(uv.x * m.width), m.width - 1);
    const int y = std::min(static_cast<int>(uv.y * m.height), m.height - 1);
    ++counts[y * m.width + x];
  }
  double chi2 = 0;
  int dof = -1;
  for (int y = 0; y < m.height; ++y) {
    for (int x = 0; x < m.width; ++x) {
      const float* t = m.texel(x, y);
      const double p = luminance({t[0], t[1], t[2]}) *
                       sh::equirect_texel_solid_angle(y, m.width, m.height) /
                       s.luminance_integral();
      const int c = counts[y * m.width + x];
      if (p == 0) {
        // Never sampled; a direction drawn on the shared edge can round into it when binned.
        EXPECT_LE(c, 2) << "black texel sampled";
        continue;
      }
      if (p * kN < 5) continue;  // too rare for the chi-square approximation
      chi2 += (c - p * kN) * (c - p * kN) / (p * kN);
      ++dof;
    }
  }
  // chi-square with ~30 dof: mean 30, sd 7.7; 80 is beyond 6 sd.
  EXPECT_LT(chi2, 80) << "dof " << dof;
}

// Inside a texel the samples are uniform in solid angle: for a one-texel-tall map (a single
// row covering the sphere) z is uniform on [-1, 1].
TEST(EnvironmentSampler, UniformInSolidAngleInsideATexel) {
  const EnvironmentSampler s(test::constant_map(1, 1, glm::vec3(2)), 0);
  Pcg32 rng(3, 0);
  double mz = 0, mz2 = 0;
  constexpr int kN = 100000;
  for (int i = 0; i < kN; ++i) {
    const auto smp = s.sample({rng.next_double(), rng.next_double()});
    EXPECT_NEAR(smp.pdf, 1 / (4 * std::numbers::pi), 1e-7);
    mz += smp.dir.z;
    mz2 += smp.dir.z * smp.dir.z;
  }
  EXPECT_NEAR(mz / kN, 0, 4 * std::sqrt(1.0 / 3 / kN));
  EXPECT_NEAR(mz2 / kN, 1.0 / 3, 0.004);
}

// Rotation about z moves the bright texel: a map whose only light is at azimuth 0 rotated by
// pi/2 shines from +y.
TEST(EnvironmentSampler, RotationTurnsTheMapCounterClockwise) {
  const auto m =
      make_map(64, 32, [](int x, int y) { return glm::vec3(x == 0 && y == 15 ? 100.0f : 0.0f); });
  const EnvironmentSampler s(m, std::numbers::pi_v<float> / 2);
  Pcg32 rng(4, 0);
  for (int i = 0; i < 100; ++i) {
    const auto smp = s.sample({rng.next_double(), rng.next_double()});
    EXPECT_GT(smp.dir.y, 0.99f);
    EXPECT_EQ(s.lookup(smp.dir).radiance, glm::vec3(100));
  }
  EXPECT_EQ(s.lookup({-0.05f, 0.998f, 0.04f}).radiance.x, 100.0f);
  EXPECT_EQ(s.lookup({0.999f, 0.0f, 0.04f}).radiance.x, 0.0f);
}

}  // namespace
}  // namespace penumbra::reference
