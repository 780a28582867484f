#include "penumbra/assets/procedural.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace penumbra::assets {
namespace {

const TerrainGrid kGrid{257, 256.0f};  // 1 m cells: grid points at whole metres

float max_height(const data::HeightField& f) {
  return *std::max_element(f.heights.begin(), f.heights.end());
}
float min_height(const data::HeightField& f) {
  return *std::min_element(f.heights.begin(), f.heights.end());
}

TEST(Procedural, GridCoversTheExtentAtAnyResolution) {
  for (int res : {2, 17, 256, 300}) {
    const data::HeightField f = sine_grating({res, 100.0f});
    EXPECT_EQ(f.width, res);
    EXPECT_EQ(f.height, res);
    EXPECT_FLOAT_EQ(f.cell_size * static_cast<float>(res - 1), 100.0f);
    for (float h : f.heights) ASSERT_TRUE(std::isfinite(h) && h >= 0);
  }
  EXPECT_THROW(cones({1, 10.0f}), std::invalid_argument);
  EXPECT_THROW(cones({64, 0.0f}), std::invalid_argument);
  EXPECT_THROW(cones({1 << 15, 10.0f}), std::invalid_argument);
  EXPECT_THROW(procedural_scene("teddy", kGrid), std::invalid_argument);
}

TEST(Procedural, ConesApexesOnARing) {
  ConesParams p;
  const data::HeightField f = cones(kGrid, p);
  // Cone i: centre 128 m + ring_radius * (cos, sin)(2 pi i / count), apex slope * r_i.
  for (int i = 0; i < p.count; ++i) {
    const float a =
        2 * std::numbers::pi_v<float> * static_cast<float>(i) / static_cast<float>(p.count);
    const float r = p.min_radius + (p.max_radius - p.min_radius) * static_cast<float>(i) /
                                       static_cast<float>(p.count - 1);
    const float cx = 128 + p.ring_radius * std::cos(a), cy = 128 + p.ring_radius * std::sin(a);
    float best = 0;
    for (int y = static_cast<int>(cy) - 1; y <= static_cast<int>(cy) + 2; ++y)
      for (int x = static_cast<int>(cx) - 1; x <= static_cast<int>(cx) + 2; ++x)
        best = std::max(best, f.at(x, y));
    EXPECT_LE(best, p.slope * r + 1e-4f) << "cone " << i;
    EXPECT_GE(best, p.slope * (r - std::numbers::sqrt2_v<float>))
        << "cone " << i;  // within a cell of the apex
  }
  EXPECT_NEAR(max_height(f), p.slope * p.max_radius, p.slope * std::numbers::sqrt2_v<float>);
  EXPECT_FLOAT_EQ(f.at(128, 128), 0.0f);  // the centre of the ring is flat ground
  EXPECT_FLOAT_EQ(f.at(0, 0), 0.0f);
}

TEST(Procedural, SineGratingPeriodAndRange) {
  SineGratingParams p;  // period 32 m along x
  const data::HeightField f = sine_grating(kGrid, p);
  for (int x = 0; x + 32 < f.width; ++x) ASSERT_NEAR(f.at(x, 5), f.at(x + 32, 5), 1e-4f) << x;
  for (int y = 0; y < f.height; ++y) ASSERT_FLOAT_EQ(f.at(7, y), f.at(7, 0));  // ridges along y
  EXPECT_NEAR(f.at(8, 0), p.amplitude, 1e-5f);  // sin peaks at a quarter period
  EXPECT_NEAR(f.at(24, 0), 0.0f, 1e-5f);
  EXPECT_NEAR(f.at(16, 0), p.amplitude / 2, 1e-5f);
  p.angle = std::numbers::pi_v<float> / 2;  // now along y
  const data::HeightField g = sine_grating(kGrid, p);
  EXPECT_NEAR(g.at(3, 8), p.amplitude, 1e-5f);
}

TEST(Procedural, EggTrayBumpsAndCups) {
  EggTrayParams p;
  const data::HeightField f = egg_tray(kGrid, p);
  EXPECT_NEAR(f.at(8, 8), p.amplitude, 1e-5f);  // sin * sin = 1
  EXPECT_NEAR(f.at(8, 24), 0.0f, 1e-5f);        // = -1: a cup
  EXPECT_NEAR(f.at(0, 13), p.amplitude / 2, 1e-5f);
  EXPECT_NEAR(f.at(40, 40), f.at(8, 8), 1e-4f);  // periodic in x and y
  EXPECT_NEAR(max_height(f), p.amplitude, 1e-5f);
  EXPECT_NEAR(min_height(f), 0.0f, 1e-5f);
}

TEST(Procedural, CityBlocksStreetsAndStoreys) {
  CityParams p;
  const data::HeightField f = city_blocks(kGrid, p);
  // Streets: the first 6 m (half a street) and every block pitch + [42, 54) m.
  for (int y = 0; y < f.height; ++y) {
    ASSERT_EQ(f.at(3, y), 0.0f);
    ASSERT_EQ(f.at(50, y), 0.0f);
  }
  int buildings = 0;
  for (float h : f.heights) {
    if (h == 0) continue;
    ++buildings;
    ASSERT_GE(h, p.min_height - p.storey / 2);
    ASSERT_LE(h, p.max_height + p.storey / 2);
    ASSERT_FLOAT_EQ(std::fmod(h, p.storey), 0.0f) << h;
  }
  EXPECT_GT(buildings, static_cast<int>(f.heights.size()) / 4);
  // A building is flat: lot of block (0, 0) spans [7, 23) m (street 6 + gap 1).
  EXPECT_GT(f.at(10, 10), 0.0f);
  EXPECT_EQ(f.at(10, 10), f.at(20, 20));
  p.seed = 2;
  EXPECT_NE(city_blocks(kGrid, p).heights, f.heights);
}

TEST(Procedural, MountainsAreDeterministicAndResolutionIndependent) {
  MountainParams p;
  const data::HeightField a = fbm_mountains(kGrid, p), b = fbm_mountains(kGrid, p);
  EXPECT_EQ(a.heights, b.heights);  // bit-identical for a seed
  for (float h : a.heights) ASSERT_TRUE(h >= 0 && h <= p.height);
  EXPECT_GT(max_height(a) - min_height(a), p.height / 4);  // actually mountainous
  // Half the resolution samples the same function at every other point.
  const data::HeightField half = fbm_mountains({129, 256.0f}, p);
  for (int y = 0; y < half.height; ++y)
    for (int x = 0; x < half.width; ++x) ASSERT_EQ(half.at(x, y), a.at(2 * x, 2 * y));
  p.seed = 99;
  const data::HeightField c = fbm_mountains(kGrid, p);
  EXPECT_NE(c.heights, a.heights);
  EXPECT_EQ(procedural_scene("mountains", kGrid, 99).heights, c.heights);
  EXPECT_EQ(procedural_scene("city", kGrid, 1).heights, city_blocks(kGrid).heights);
}

}  // namespace
}  // namespace penumbra::assets
