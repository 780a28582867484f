// The height field's shadow on points above it ([Giraud] sec. 4.1, "Height Field Cast Shadows").
#include "penumbra/systems/terrain_shadow/cast_shadow.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include "common/stability.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

data::HeightField walled(int n) {
  data::HeightField f;
  f.width = f.height = n;
  f.cell_size = 1;
  f.heights.assign(static_cast<std::size_t>(n) * n, 0.0f);
  for (int y = 0; y < n; ++y) f.at(n / 2, y) = 10.0f;  // a 10 m wall along x = n / 2
  f.source = "walled";
  return f;
}

// Fraction of the sphere a primal SH visibility says is visible (its mean value).
float visible_fraction(const sh::Coeffs<4>& v) {
  return v[0] / std::sqrt(4 * kPi);
}

TEST(CastShadow, HorizonsSeeTheWallOnOneSideOnly) {
  const auto f = walled(32);
  const std::vector<float> a = point_horizons(f, 1.0f, {10.0f, 16.0f, 2.0f}, 8);
  EXPECT_NEAR(a[0], std::atan(8.0f / 6.0f), 1e-5f);  // towards +x: the wall 6 m away, 8 m up
  EXPECT_LT(a[4], 0.0f);                             // towards -x: only ground below the point
}

TEST(CastShadow, PrimalVisibilityDropsNearTheWallAndBelowTheSurface) {
  const auto f = walled(32);
  const WedgeTable<4> sphere(16, WedgeDomain::kSphere);
  const float open = visible_fraction(cast_shadow_visibility<4>(f, 1, {4, 16, 30}, sphere));
  const float near_wall = visible_fraction(cast_shadow_visibility<4>(f, 1, {14, 16, 1}, sphere));
  // 5 m under the ground: every azimuth sees the ground rise at atan(5 / 1) next to it.
  const float buried = visible_fraction(cast_shadow_visibility<4>(f, 1, {4, 16, -5}, sphere));
  EXPECT_GT(open, 0.5f);  // high above: the ground hides less than the lower hemisphere
  EXPECT_LT(near_wall, open - 0.1f);
  EXPECT_LT(buried, 0.08f);  // exact: (1 - sin(atan 5)) / 2 = 0.010, plus SH ringing
}

TEST(CastShadow, LogVisibilityIsTheLogWedgeSumOfThePointsHorizons) {
  const auto f = walled(32);
  const LogWedge<4> wedges(16, std::log(1e-3f));
  const glm::vec3 p(12, 16, 3);
  const sh::Coeffs<4> v = cast_shadow_log_visibility<4>(f, 1, p, wedges);
  const std::vector<float> a = point_horizons(f, 1, p, 16);
  const sh::Coeffs<4> expected = wedges.log_visibility(a.data());
  for (int i = 0; i < 16; ++i) EXPECT_EQ(v[i], expected[i]);
  EXPECT_LT(v[0], 0.0f);  // some directions are blocked: negative log-visibility mass
}

TEST(CastShadow, RejectsNonFinitePointsAndHemisphereTables) {
  PENUMBRA_STABILITY("a non-finite cast-shadow point; a hemisphere wedge table",
                     "std::invalid_argument", "caller passes finite points and a sphere table");
  const auto f = walled(8);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(point_horizons(f, 1, {nan, 1, 1}, 8), std::invalid_argument);
  const WedgeTable<4> hemi(8, WedgeDomain::kHemisphere);
  EXPECT_THROW(cast_shadow_visibility<4>(f, 1, {1, 1, 1}, hemi), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
