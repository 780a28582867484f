// Multi-scale horizon march ([Meier13] eq. 4.5-4.14, 4.22-4.25) against exact
// cases and the brute-force ray march; tolerances are measured errors with some margin.
#include "penumbra/systems/terrain_shadow/horizon_march.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>

#include "common/stability.h"
#include "penumbra/assets/procedural.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

// A cliff: height h from column x on, 0 before.
data::HeightField cliff(int n, int x0, float h) {
  data::HeightField f = test::flat_field(n, n, 0.0f, 1.0f, "test field");
  for (int y = 0; y < n; ++y)
    for (int x = x0; x < n; ++x) f.at(x, y) = h;
  return f;
}

HorizonGrid march(const data::HeightField& f, const HorizonParams& p, int ls, float lo) {
  HeightPyramid pyramid;
  pyramid.build(f, p.height_scale, {ls});
  HorizonGrid out;
  march_horizons(pyramid, p, {lo}, TexelRect::all(f), out);
  return out;
}

HorizonGrid brute(const data::HeightField& f, const HorizonParams& p) {
  HorizonGrid out;
  brute_force_horizons(f, p, TexelRect::all(f), out);
  return out;
}

double mean_abs_error(const HorizonGrid& a, const HorizonGrid& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.angles.size(); ++i) sum += std::abs(a.angles[i] - b.angles[i]);
  return sum / static_cast<double>(a.angles.size());
}

TEST(HorizonMarch, FlatTerrain) {
  PENUMBRA_STABILITY("flat terrain; a receiver at the field's edge; a light straight above",
                     "horizon 0 inside, -pi/2 past the edge and above: no NaN", "-");
  const auto f = test::flat_field(24, 24, 0.0f, 1.0f, "test field");
  HorizonParams p;
  p.azimuths = 8;
  const HorizonGrid clamped = march(f, p, 4, 2.0f);
  for (float a : clamped.angles) ASSERT_EQ(a, 0.0f);

  p.clamp_at_zero = false;
  const HorizonGrid open = march(f, p, 4, 2.0f);
  EXPECT_NEAR(open.texel(10, 10)[3], 0.0f, 1e-6f);
  // Corner (0, 0): nothing towards -x (azimuth 4 = pi) or -y (azimuth 6): the field ends.
  EXPECT_FLOAT_EQ(open.texel(0, 0)[4], -kPi / 2);
  EXPECT_FLOAT_EQ(open.texel(0, 0)[6], -kPi / 2);
  EXPECT_NEAR(open.texel(0, 0)[0], 0.0f, 1e-6f);

  // A local light straight above the receiver: no terrain in range in any direction.
  p.limit_to_point = glm::vec2(10.0f, 10.0f);
  const HorizonGrid above = march(f, p, 4, 2.0f);
  for (int k = 0; k < 8; ++k) EXPECT_FLOAT_EQ(above.texel(10, 10)[k], -kPi / 2) << k;
  EXPECT_NEAR(above.texel(2, 10)[0], 0.0f, 1e-6f);  // 8 cells away: flat ground in range
}

TEST(HorizonMarch, CliffSeenAlongTheAxis) {
  // Receivers at x < 40 looking along +x (azimuth 0) see the cliff's edge at atan(h / distance).
  const auto f = cliff(64, 40, 20.0f);
  HorizonParams p;
  p.azimuths = 4;
  const HorizonGrid exact = brute(f, p);
  const HorizonGrid sharp = march(f, p, 4, 4.0f);
  for (int x : {10, 20, 30, 36, 39}) {
    const float expected = std::atan(20.0f / static_cast<float>(40 - x));
    EXPECT_NEAR(exact.texel(x, 32)[0], expected, 1e-5f) << x;
    // Samples fall up to a spacing past the edge and the B-spline (knot weights 1/6 2/3 1/6)
    // averages them with the flat ground before it: measured at most 0.11 rad low.
    EXPECT_NEAR(sharp.texel(x, 32)[0], expected, 0.2f) << x;
    EXPECT_LE(sharp.texel(x, 32)[0], expected + 1e-3f) << x;
  }
  // Looking away from the cliff (azimuth 2 = pi): flat, clamped to 0.
  EXPECT_EQ(sharp.texel(30, 32)[2], 0.0f);
}

TEST(HorizonMarch, CloseToBruteForceOnProceduralTerrain) {
  // Mean absolute error in radians, 64 x 64 samples of each scene on 256 m, 32 azimuths,
  // ls = 4, lo = 2. Measured: mountains 0.012 (clamped) / 0.014, cones 0.014 / 0.015.
  for (const char* scene : {"mountains", "cones"}) {
    const auto f = assets::procedural_scene(scene, {64, 256.0f}, 3);
    for (bool clamp : {true, false}) {
      HorizonParams p;
      p.clamp_at_zero = clamp;
      const double error = mean_abs_error(march(f, p, 4, 2.0f), brute(f, p));
      EXPECT_LT(error, 0.02) << scene << " clamp " << clamp;
    }
  }
}

TEST(HorizonMarch, LargerLevelOffsetIsSharper) {
  // Finer pyramid levels for the far samples: the error against brute force falls with lo on
  // the city's sharp building edges (measured 0.167, 0.108, 0.091, 0.088 for lo = 0..3).
  const auto f = assets::procedural_scene("city", {64, 256.0f}, 3);
  HorizonParams p;
  double previous = 1e9;
  for (float lo : {0.0f, 1.0f, 2.0f, 3.0f}) {
    const double error = mean_abs_error(march(f, p, 4, lo), brute(f, p));
    EXPECT_LT(error, previous) << "lo " << lo;
    previous = error;
  }
  EXPECT_LT(previous, 0.1);
}

TEST(HorizonMarch, LocalLightIgnoresOccludersBeyondIt) {
  // Cliff at x = 50; light at x = 30 m on row 32. Receivers at x <= 20 see flat ground up to
  // the light along +x, and the cliff without the limit.
  const auto f = cliff(64, 50, 30.0f);
  HorizonParams p;
  p.azimuths = 16;
  p.clamp_at_zero = false;
  const HorizonGrid unlimited = march(f, p, 4, 2.0f);
  p.limit_to_point = glm::vec2(30.0f, 32.0f);
  const HorizonGrid limited = march(f, p, 4, 2.0f);
  for (int x : {5, 12, 20}) {
    EXPECT_GT(unlimited.texel(x, 32)[0], 0.3f) << x;
    EXPECT_NEAR(limited.texel(x, 32)[0], 0.0f, 1e-5f) << x;
  }
  // Overall close to the brute force with the same limit (measured 0.015).
  EXPECT_LT(mean_abs_error(limited, brute(f, p)), 0.05);
  // With the light on the cliff, its edge is in range.
  p.limit_to_point = glm::vec2(60.0f, 32.0f);
  const HorizonGrid beyond = march(f, p, 4, 2.0f);
  for (int x : {5, 12, 20}) EXPECT_GT(beyond.texel(x, 32)[0], 0.3f) << x;

  const auto hills = assets::procedural_scene("mountains", {48, 192.0f}, 7);
  p.azimuths = 32;
  p.limit_to_point = glm::vec2(100.0f, 60.0f);  // measured 0.012
  EXPECT_LT(mean_abs_error(march(hills, p, 4, 2.0f), brute(hills, p)), 0.03);
}

TEST(HorizonMarch, TilesMatchTheWholeFieldAndRunConcurrently) {
  const auto f = assets::procedural_scene("mountains", {40, 160.0f}, 2);
  for (bool light : {false, true}) {
    HorizonParams p;
    p.azimuths = 12;
    if (light) {
      p.clamp_at_zero = false;
      p.limit_to_point = glm::vec2(50.0f, 90.0f);
    }
    HeightPyramid pyramid;
    pyramid.build(f, 1.0f, {4});
    HorizonGrid whole, tiled;
    march_horizons(pyramid, p, {}, TexelRect::all(f), whole);
    tiled.resize(40, 40, 12);  // sized first: concurrent calls must not resize
    auto run = [&](int part) {
      for (int ty = 0; ty < 40; ty += 16)
        for (int tx = part * 8; tx < 40; tx += 16)
          march_horizons(pyramid, p, {}, {tx, ty, std::min(tx + 8, 40), std::min(ty + 16, 40)},
                         tiled);
    };
    std::thread other(run, 1);
    run(0);
    other.join();
    EXPECT_EQ(whole.angles, tiled.angles) << "light " << light;
  }
}

TEST(HorizonMarch, WritesOnlyTheRegion) {
  const auto f = assets::procedural_scene("cones", {32, 128.0f}, 1);
  HeightPyramid pyramid;
  pyramid.build(f, 1.0f, {4});
  HorizonParams p;
  p.azimuths = 6;
  HorizonGrid out;
  out.resize(32, 32, 6);
  std::fill(out.angles.begin(), out.angles.end(), 9.0f);
  const TexelRect r{5, 7, 19, 12};
  march_horizons(pyramid, p, {}, r, out);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      for (int k = 0; k < 6; ++k) {
        const float a = out.texel(x, y)[k];
        if (r.contains(x, y)) {
          ASSERT_TRUE(a >= 0.0f && a <= kPi / 2) << x << ", " << y;
        } else {
          ASSERT_EQ(a, 9.0f) << x << ", " << y;
        }
      }
}

TEST(HorizonMarch, RejectsBadInputNamingTheField) {
  PENUMBRA_STABILITY("an empty pyramid or bad march parameters",
                     "std::invalid_argument naming the field", "-");
  const auto f = test::flat_field(16, 16, 0.0f, 1.0f, "test field");
  HeightPyramid pyramid;
  pyramid.build(f, 1.0f, {4});
  HorizonGrid out;
  auto expect_error = [&](const HeightPyramid& pyr, const HorizonParams& p, const MarchParams& m,
                          const TexelRect& r) {
    try {
      march_horizons(pyr, p, m, r, out);
      ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("test field"), std::string::npos) << e.what();
    }
  };
  const HorizonParams ok;
  const TexelRect all = TexelRect::all(f);
  HorizonParams few = ok;
  few.azimuths = 2;
  expect_error(pyramid, few, {}, all);
  expect_error(pyramid, ok, {-1.0f}, all);
  expect_error(pyramid, ok, {std::nanf("")}, all);
  expect_error(pyramid, ok, {INFINITY}, all);
  expect_error(pyramid, ok, {}, {0, 0, 17, 16});
  expect_error(pyramid, ok, {}, {-1, 0, 4, 4});
  HorizonParams bad_light = ok;
  bad_light.limit_to_point = glm::vec2(NAN, 0.0f);
  expect_error(pyramid, bad_light, {}, all);
  EXPECT_THROW(march_horizons(HeightPyramid{}, ok, {}, all, out), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
