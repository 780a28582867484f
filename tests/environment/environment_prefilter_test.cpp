// The input check, luminance (eq. 3.1) and the Gaussian prefilter (environment_prefilter.h).
#include "penumbra/systems/environment/environment_prefilter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "common/stability.h"
#include "synthetic_maps.h"

namespace env = penumbra::environment;
namespace t = penumbra::test;

namespace {

// The message of the std::invalid_argument `f` throws ("" if none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(EnvironmentPrefilter, LuminanceIsEq3_1) {
  const float white[3] = {1, 1, 1}, red[3] = {1, 0, 0};
  EXPECT_FLOAT_EQ(env::luminance(white), 179.0f);
  EXPECT_FLOAT_EQ(env::luminance(red), 179.0f * 0.265f);
}

TEST(EnvironmentPrefilter, ConstantImageUnchanged) {
  const std::vector<float> img(64 * 32, 2.5f);
  const std::vector<float> out = env::gaussian_prefilter(img, 64, 32, 4);
  for (float v : out) EXPECT_NEAR(v, 2.5f, 1e-5f);
}

TEST(EnvironmentPrefilter, WrapsAroundTheSeamAndKeepsTheSum) {
  std::vector<float> img(64 * 32, 0.0f);
  img[16 * 64 + 0] = 1.0f;  // column 0, a middle row
  const std::vector<float> out = env::gaussian_prefilter(img, 64, 32, 4);
  EXPECT_GT(out[16 * 64 + 63], 0.02f);  // spread across the seam to the last column
  EXPECT_NEAR(out[16 * 64 + 63], out[16 * 64 + 1], 1e-6f);
  EXPECT_NEAR(std::accumulate(out.begin(), out.end(), 0.0), 1.0, 1e-5);
}

TEST(EnvironmentPrefilter, RadiusZeroIsIdentityAndBadRadiusThrows) {
  PENUMBRA_STABILITY("radius 0; negative or too large radius; wrong size",
                     "0: identity; others std::invalid_argument naming the radius", "-");
  std::vector<float> img(16 * 8);
  std::iota(img.begin(), img.end(), 0.0f);
  EXPECT_EQ(env::gaussian_prefilter(img, 16, 8, 0), img);
  EXPECT_NE(error_of([&] { env::gaussian_prefilter(img, 16, 8, -1); }).find("radius -1"),
            std::string::npos);
  EXPECT_NE(error_of([&] { env::gaussian_prefilter(img, 16, 8, 8); }).find("radius 8"),
            std::string::npos);
  EXPECT_NE(error_of([&] { env::gaussian_prefilter(img, 16, 9, 2); }).find("does not match"),
            std::string::npos);
}

// Policy: NaN, infinite and negative texels are rejected, naming the map and the texel.
TEST(EnvironmentPrefilter, RejectsNanInfNegativeNamingTheInput) {
  PENUMBRA_STABILITY("NaN, infinite and negative texels",
                     "rejected, naming the map, the texel and the channel", "-");
  auto m = t::flat_map(8, 4, glm::vec3(1), "nan_map.exr");
  m.rgb[3 * (2 * 8 + 3) + 1] = std::numeric_limits<float>::quiet_NaN();
  std::string e = error_of([&] { env::check_environment_map(m); });
  EXPECT_NE(e.find("nan_map.exr"), std::string::npos) << e;
  EXPECT_NE(e.find("texel (3, 2) channel G is NaN"), std::string::npos) << e;

  m.rgb[3 * (2 * 8 + 3) + 1] = std::numeric_limits<float>::infinity();
  e = error_of([&] { env::check_environment_map(m); });
  EXPECT_NE(e.find("is infinite"), std::string::npos) << e;

  m.rgb[3 * (2 * 8 + 3) + 1] = -0.5f;
  e = error_of([&] { env::check_environment_map(m); });
  EXPECT_NE(e.find("is negative"), std::string::npos) << e;
}

TEST(EnvironmentPrefilter, RejectsBadSizes) {
  PENUMBRA_STABILITY("a map whose float count does not match its size",
                     "rejected naming the map and the count", "-");
  auto m = t::flat_map(8, 4, glm::vec3(1), "small.exr");
  m.rgb.pop_back();
  EXPECT_NE(error_of([&] { env::check_environment_map(m); }).find("small.exr: 95 floats"),
            std::string::npos);
  penumbra::data::EnvironmentMap empty;
  EXPECT_NE(error_of([&] {
              env::check_environment_map(empty);
            }).find("environment map: size 0x0 is not positive"),
            std::string::npos);
}

}  // namespace
