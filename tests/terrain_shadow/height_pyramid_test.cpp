// Height pyramid ([Meier13] eq. 4.4, sec. 5.1): level count, level 0, the
// low-pass filtering of the other levels, bilinear sampling and input errors.
#include "penumbra/systems/terrain_shadow/height_pyramid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>

#include "common/stability.h"
#include "penumbra/assets/procedural.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

data::HeightField noise(int n, std::uint32_t seed) {
  data::HeightField f = test::flat_field(n, n, 0.0f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (float& v : f.heights) v = u(rng);
  return f;
}

double variance(const HeightPyramid& p, int level) {
  const std::size_t count = static_cast<std::size_t>(p.width()) * p.height();
  const float* d = p.level_data(level);
  double mean = 0, sq = 0;
  for (std::size_t i = 0; i < count; ++i) mean += d[i];
  mean /= static_cast<double>(count);
  for (std::size_t i = 0; i < count; ++i) sq += (d[i] - mean) * (d[i] - mean);
  return sq / static_cast<double>(count);
}

TEST(HeightPyramid, LevelCountFollowsEq4_4) {
  struct Case {
    int w, h, ls, levels;  // levels = ceil(ls * log2(max(w, h))) + 1
  };
  for (const Case c : {Case{2, 2, 1, 2}, Case{64, 64, 4, 25}, Case{64, 64, 1, 7}, Case{65, 3, 1, 8},
                       Case{37, 100, 3, 21}, Case{128, 16, 2, 15}}) {
    HeightPyramid p;
    p.build(test::flat_field(c.w, c.h, 1.0f, 2.0f), 1.0f, {c.ls});
    EXPECT_EQ(p.levels(), c.levels) << c.w << " x " << c.h << ", ls " << c.ls;
    EXPECT_EQ(p.width(), c.w);
    EXPECT_EQ(p.height(), c.h);
    EXPECT_EQ(p.level_step(), c.ls);
    EXPECT_FLOAT_EQ(p.cell_size(), 2.0f);
  }
}

TEST(HeightPyramid, LevelZeroIsTheScaledInput) {
  const auto f = assets::procedural_scene("mountains", {48, 96.0f}, 5);
  HeightPyramid p;
  p.build(f, 2.5f, {4});
  for (std::size_t i = 0; i < f.heights.size(); ++i)
    ASSERT_EQ(p.level_data(0)[i], 2.5f * f.heights[i]) << "sample " << i;
  EXPECT_EQ(p.source(), f.source);
}

TEST(HeightPyramid, ConstantFieldStaysConstantOnEveryLevel) {
  HeightPyramid p;
  p.build(test::flat_field(40, 23, 7.0f), 3.0f, {3});
  for (int level = 0; level < p.levels(); ++level)
    for (int i = 0; i < 40 * 23; ++i)
      ASSERT_NEAR(p.level_data(level)[i], 21.0f, 1e-4f) << "level " << level << " sample " << i;
}

TEST(HeightPyramid, CoarserLevelsAreSmoother) {
  // Strictly decreasing while the kernel (about 3 s wide) fits in the field: s <= 16 cells.
  // Coarser, the few border-clamped coefficients left make it fluctuate at ~0.3% of level 0.
  HeightPyramid p;
  p.build(noise(64, 11), 1.0f, {4});
  double previous = variance(p, 0);
  for (int level = 1; level <= 16; ++level) {
    const double v = variance(p, level);
    EXPECT_LT(v, previous) << "level " << level;
    previous = v;
  }
  EXPECT_LT(variance(p, 4), 0.3 * variance(p, 0));  // s = 2
  EXPECT_LT(variance(p, 16), 0.01 * variance(p, 0));
  for (int level = 17; level < p.levels(); ++level)
    EXPECT_LT(variance(p, level), 0.005 * variance(p, 0)) << "level " << level;
}

TEST(HeightPyramid, ImpulseSpreadsOverAboutTheLevelSpacing) {
  // Level i is filtered for spacing s = 2^(i / ls): a tent of half-width s, then a B-spline
  // with knots s apart, so a single spike spreads to at most 3 s cells and its peak drops.
  const int n = 65, c = 32;
  data::HeightField f = test::flat_field(n, n, 0.0f);
  f.at(c, c) = 1.0f;
  HeightPyramid p;
  p.build(f, 1.0f, {2});
  float previous_peak = 1.0f;
  for (int level = 1; level < p.levels(); ++level) {
    const double s = std::exp2(level / 2.0);
    const float* d = p.level_data(level);
    float peak = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const float v = d[y * n + x];
        peak = std::max(peak, v);
        if (std::max(std::abs(x - c), std::abs(y - c)) > 3 * s + 1) {
          ASSERT_NEAR(v, 0.0f, 1e-6f) << "level " << level << " at (" << x << ", " << y << ")";
        }
      }
    EXPECT_LT(peak, previous_peak) << "level " << level;
    previous_peak = peak;
  }
}

TEST(HeightPyramid, SamplingIsBilinearAndClampedToTheBorder) {
  HeightPyramid p;
  p.build(noise(16, 3), 1.0f, {2});
  for (int level : {0, 3, p.levels() - 1}) {
    const float* d = p.level_data(level);
    auto at = [&](int x, int y) { return d[y * 16 + x]; };
    EXPECT_FLOAT_EQ(p.sample(level, 5, 7), at(5, 7));
    const float top = at(5, 7) + 0.25f * (at(6, 7) - at(5, 7));
    const float bottom = at(5, 8) + 0.25f * (at(6, 8) - at(5, 8));
    EXPECT_NEAR(p.sample(level, 5.25f, 7.5f), top + 0.5f * (bottom - top), 1e-6f);
    EXPECT_FLOAT_EQ(p.sample(level, -3.0f, -0.5f), at(0, 0));
    EXPECT_FLOAT_EQ(p.sample(level, 15.0f, 15.0f), at(15, 15));
    EXPECT_NEAR(p.sample(level, 40.0f, 2.5f), 0.5f * (at(15, 2) + at(15, 3)), 1e-6f);
  }
}

TEST(HeightPyramid, RebuildsAtAnotherSize) {
  HeightPyramid p;
  p.build(noise(32, 1), 1.0f, {4});
  p.build(test::flat_field(8, 5, 2.0f), 1.0f, {1});
  EXPECT_EQ(p.levels(), 4);
  for (int level = 0; level < p.levels(); ++level)
    EXPECT_NEAR(p.sample(level, 3.5f, 2.5f), 2.0f, 1e-5f);
}

TEST(HeightPyramid, RejectsBadInputNamingTheField) {
  PENUMBRA_STABILITY("level step 0 or 17, a 1-wide field, cell size 0",
                     "std::invalid_argument naming the field", "-");
  auto expect_error = [](const data::HeightField& f, float scale, int ls) {
    HeightPyramid p;
    try {
      p.build(f, scale, {ls});
      ADD_FAILURE() << "no error for ls " << ls;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("flat"), std::string::npos) << e.what();
    }
  };
  expect_error(test::flat_field(8, 8, 0.0f), 1.0f, 0);
  expect_error(test::flat_field(8, 8, 0.0f), 1.0f, 17);
  expect_error(test::flat_field(1, 8, 0.0f), 1.0f, 4);
  expect_error(test::flat_field(8, 8, 0.0f, 0.0f), 1.0f, 4);
  expect_error(test::flat_field(8, 8, 0.0f), std::nanf(""), 4);
  data::HeightField bad = test::flat_field(8, 8, 0.0f);
  bad.at(3, 4) = INFINITY;
  expect_error(bad, 1.0f, 4);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
