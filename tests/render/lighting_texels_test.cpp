// RGBM packing of the terrain's lighting texels (lighting_texels.h): the stated precision, dark
// texels keeping relative precision, and bad input.
#include "penumbra/render/lighting_texels.h"
#include "common/random_draws.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <glm/vec4.hpp>

namespace penumbra::render {
namespace {

std::vector<std::uint8_t> pack(const std::vector<glm::vec3>& rgb, RgbmPacking* p = nullptr) {
  std::vector<std::uint8_t> out(4 * rgb.size(), 0xAB);
  const RgbmPacking r = pack_rgbm(rgb.data(), rgb.size(), out.data());
  if (p) *p = r;
  return out;
}

TEST(LightingTexels, RoundTripWithinTheStatedBound) {
  // Irradiance-like values over four decades, coloured.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> decade(-4.0f, 0.0f), tint(0.3f, 1.0f);
  std::vector<glm::vec3> rgb(5000);
  for (auto& c : rgb) {
    const float ty = tint(rng), tx = tint(rng), d = decade(rng);  // GCC's order (random_draws.h)
    c = std::pow(10.0f, d) * 20.0f * glm::vec3(tx, ty, 1.0f);
  }
  RgbmPacking p;
  const auto packed = pack(rgb, &p);
  float largest = 0.0f;
  for (const auto& c : rgb) largest = std::max({largest, c.x, c.y, c.z});
  EXPECT_FLOAT_EQ(p.scale, largest);
  EXPECT_EQ(p.rejected, 0u);
  float worst_relative = 0.0f;
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const glm::vec3 d = unpack_rgbm(&packed[4 * i], p.scale);
    const float m = std::max({rgb[i].x, rgb[i].y, rgb[i].z});
    const float bound = m / 510.0f + p.scale / 130050.0f;
    for (int c = 0; c < 3; ++c) {
      ASSERT_LE(std::abs(d[c] - rgb[i][c]), bound * 1.001f) << i << " channel " << c;
      if (m > p.scale * 0.01f)
        worst_relative = std::max(worst_relative, std::abs(d[c] - rgb[i][c]) / m);
    }
  }
  // Within two decades of the brightest texel, every channel within 0.4% of the texel's largest
  // (half floats: 0.05%), the precision an 8-bit display shows after tone mapping.
  EXPECT_LT(worst_relative, 0.004f);
}

// Eight texels a step (AVX2) and one at a time give the same bytes, bad texels and a tail that
// is not a multiple of eight included.
TEST(LightingTexels, LanesEqualOneAtATime) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const std::size_t n : {std::size_t{0}, std::size_t{5}, std::size_t{64}, std::size_t{1003}}) {
    std::vector<glm::vec3> rgb(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float level = std::pow(10.0f, -4.0f + 6.0f * u(rng));  // 1e-4 .. 100
      rgb[i] = level * penumbra::test::draw_zyx<glm::vec3>(rng, u);
      if (i % 97 == 3) rgb[i].y = std::numeric_limits<float>::quiet_NaN();
      if (i % 89 == 5) rgb[i].x = -1.0f;
      if (i % 83 == 7) rgb[i] = glm::vec3(0.0f);
    }
    std::vector<std::uint8_t> lanes(4 * n, 1), scalar(4 * n, 2);
    const RgbmPacking a = pack_rgbm(rgb.data(), n, lanes.data());
    const RgbmPacking b = pack_rgbm_scalar(rgb.data(), n, scalar.data());
    EXPECT_EQ(a.scale, b.scale) << n;
    EXPECT_EQ(a.rejected, b.rejected) << n;
    EXPECT_EQ(lanes, scalar) << n;
  }
}

TEST(LightingTexels, BrightestTexelIsExactAndBlackIsZero) {
  const std::vector<glm::vec3> rgb{{4.0f, 2.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
  RgbmPacking p;
  const auto packed = pack(rgb, &p);
  EXPECT_EQ(packed[3], 255);
  EXPECT_EQ(packed[0], 255);
  EXPECT_FLOAT_EQ(unpack_rgbm(&packed[0], p.scale).x, 4.0f);
  for (int c = 4; c < 8; ++c) EXPECT_EQ(packed[c], 0);
}

TEST(LightingTexels, BadTexelsBecomeBlackAndAreCounted) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<glm::vec3> rgb{
      {1.0f, 1.0f, 1.0f}, {nan, 1.0f, 1.0f}, {inf, 0.0f, 0.0f}, {-1.0f, 2.0f, 2.0f}};
  RgbmPacking p;
  const auto packed = pack(rgb, &p);
  EXPECT_EQ(p.rejected, 3u);
  EXPECT_FLOAT_EQ(p.scale, 1.0f);  // the bad texels do not set the scale
  for (int i = 1; i < 4; ++i)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(packed[4 * i + c], 0) << i;
}

TEST(LightingTexels, EmptyAndAllBlackGiveScaleOne) {
  EXPECT_FLOAT_EQ(pack_rgbm(nullptr, 0, nullptr).scale, 1.0f);
  RgbmPacking p;
  pack(std::vector<glm::vec3>(3, glm::vec3(0.0f)), &p);
  EXPECT_FLOAT_EQ(p.scale, 1.0f);
}

// What bilinear filtering does to a shadow edge: the texel between a lit texel (the terrain's
// brightest) and a shadowed one, decoded from the filtered RGBM against the filtered values.
// Measured sizes (docs/play.md): within 1% while the shadow is at least 1/20 of the brightest,
// 7% at 1/50-1/100 (the multiplier's few steps there leave the shadowed colour at 0.85), and
// exact again at 1/255 (one whole step).
TEST(LightingTexels, ShadowEdgeMidpointError) {
  auto midpoint_error = [](float ratio) {
    const std::vector<glm::vec3> rgb{glm::vec3(1.0f), glm::vec3(1.0f / ratio)};
    std::vector<std::uint8_t> t(8);
    const RgbmPacking p = pack_rgbm(rgb.data(), 2, t.data());
    glm::vec4 f(0.0f);  // the sampler's blend at 0.5, in unorm
    for (int c = 0; c < 4; ++c) f[c] = 0.5f * (t[c] + t[4 + c]) / 255.0f;
    const float decoded = f.x * f.w * p.scale;
    const float exact = 0.5f * (1.0f + 1.0f / ratio);
    return std::abs(decoded - exact) / exact;
  };
  EXPECT_LT(midpoint_error(2.0f), 0.002f);
  EXPECT_LT(midpoint_error(10.0f), 0.01f);
  EXPECT_LT(midpoint_error(20.0f), 0.01f);
  EXPECT_LT(midpoint_error(100.0f), 0.08f);
  EXPECT_GT(midpoint_error(100.0f), 0.05f) << "the documented size";
}

}  // namespace
}  // namespace penumbra::render
