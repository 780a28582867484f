// Light-source detection on synthetic maps ([Ambrosj16] sec. 4.1 with Penumbra's deviations,
// docs/environment.md): discs ("suns") of known direction, radius and radiance on a flat sky,
// 512 x 256 texels (0.70 degrees per texel) like ../shared/data/hdri.
//
// Tolerances: a disc's direction within 0.5 degrees (under one texel); its angular radius, 3
// standard deviations of its prefiltered core, between 1.0x and 2.0x the disc's radius (a
// uniform disc's largest standard deviation is r / 2, so 3 sigma is 1.5 r, widened by the
// radius-4 prefilter); its energy share within 5% (relative) of the disc's true share.
#include "penumbra/systems/environment/light_source_detection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/stability.h"
#include "synthetic_maps.h"

namespace env = penumbra::environment;
namespace t = penumbra::test;

namespace {

constexpr int kW = 512, kH = 256;
const glm::vec3 kSky(0.3f, 0.4f, 0.6f);

void print(const char* name, const env::LightSourceDetection& d) {
  std::printf("%s: %zu sources (%.2f ms)%s%s\n", name, d.sources.size(), d.milliseconds,
              d.stop.empty() ? "" : ", stop: ", d.stop.c_str());
  for (const auto& s : d.sources)
    std::printf("  az %.2f el %.2f radius %.2f deg share %.4f texels %zu contrast %.1f\n",
                static_cast<double>(s.azimuth_deg), static_cast<double>(s.elevation_deg),
                static_cast<double>(s.angular_radius / t::kDeg),
                static_cast<double>(s.energy_share), s.texels.size(),
                static_cast<double>(s.peak_contrast));
}

void expect_disc(const env::DetectedSource& s, const penumbra::data::EnvironmentMap& m,
                 glm::vec3 dir, float radius_deg) {
  EXPECT_LT(t::angle_deg(s.direction, dir), 0.5f);
  EXPECT_GE(s.angular_radius / t::kDeg, 1.0f * radius_deg);
  EXPECT_LE(s.angular_radius / t::kDeg, 2.0f * radius_deg);
  const double share = t::luminous_energy(m, dir, radius_deg) / t::luminous_energy(m);
  EXPECT_NEAR(s.energy_share, share, 0.05 * share);
}

TEST(LightSourceDetection, DiscSunFoundWithItsDirectionRadiusAndShare) {
  auto m = t::flat_map(kW, kH, kSky);
  const glm::vec3 sun = t::dir_deg(60, 35);
  t::add_disc(m, sun, 3.0f, glm::vec3(3000, 2800, 2500));
  env::DetectionSettings s;
  s.source_count = 1;
  const auto d = env::detect_light_sources(m, s);
  print("disc", d);
  ASSERT_EQ(d.sources.size(), 1u);
  expect_disc(d.sources[0], m, sun, 3.0f);
  float az = 0, el = 0;
  env::azimuth_elevation(d.sources[0].direction, az, el);
  EXPECT_NEAR(az, 60.0f, 0.6f);
  EXPECT_NEAR(el, 35.0f, 0.5f);
  // Radiance and irradiance of the removed texels: the disc's colour, diluted by the sky
  // texels of the prefiltered rim it also removes.
  EXPECT_GT(d.sources[0].radiance.r, d.sources[0].radiance.b);
  EXPECT_NEAR(d.sources[0].irradiance.g / d.sources[0].solid_angle, d.sources[0].radiance.g,
              1e-2f * d.sources[0].radiance.g);
}

TEST(LightSourceDetection, TwoSunsBrightestFirst) {
  auto m = t::flat_map(kW, kH, kSky);
  const glm::vec3 a = t::dir_deg(60, 35), b = t::dir_deg(250, 10);
  t::add_disc(m, a, 3.0f, glm::vec3(3000));
  t::add_disc(m, b, 4.0f, glm::vec3(800));
  const auto d = env::detect_light_sources(m);  // source_count 2
  print("two suns", d);
  ASSERT_EQ(d.sources.size(), 2u);
  expect_disc(d.sources[0], m, a, 3.0f);
  expect_disc(d.sources[1], m, b, 4.0f);
  for (std::uint32_t i : d.sources[0].texels)  // disjoint texel sets
    EXPECT_FALSE(std::binary_search(d.sources[1].texels.begin(), d.sources[1].texels.end(), i));
}

// A sun on the longitude seam (azimuth 0: half of it in column 0, half in the last column) is
// one source on unit directions; 003's pixel-coordinate distance puts its mean mid-map.
TEST(LightSourceDetection, SunOnTheSeam) {
  auto m = t::flat_map(kW, kH, kSky);
  const glm::vec3 sun = t::dir_deg(0, 20);
  t::add_disc(m, sun, 3.0f, glm::vec3(2000));
  env::DetectionSettings s;
  s.source_count = 1;
  const auto d = env::detect_light_sources(m, s);
  print("seam", d);
  ASSERT_EQ(d.sources.size(), 1u);
  expect_disc(d.sources[0], m, sun, 3.0f);

  s.cluster_space = env::ClusterSpace::kPixelCoordinates;
  s.halo_set = env::HaloSet::kNearestCentroid;  // 003 as written
  const auto p = env::detect_light_sources(m, s);
  print("seam, 003 pixel distance", p);
  ASSERT_EQ(p.sources.size(), 1u);
  EXPECT_LT(p.sources[0].energy_share, 0.6 * d.sources[0].energy_share);  // half the sun at most
}

TEST(LightSourceDetection, SunAtThePole) {
  auto m = t::flat_map(kW, kH, kSky);
  const glm::vec3 sun(0, 0, 1);
  t::add_disc(m, sun, 5.0f, glm::vec3(2000));
  env::DetectionSettings s;
  s.source_count = 1;
  const auto d = env::detect_light_sources(m, s);
  print("pole", d);
  ASSERT_EQ(d.sources.size(), 1u);
  expect_disc(d.sources[0], m, sun, 5.0f);
  EXPECT_NEAR(d.sources[0].elevation_deg, 90.0f, 0.5f);
}

TEST(LightSourceDetection, OneTexelSun) {
  auto m = t::flat_map(kW, kH, kSky);
  const std::size_t texel = 60 * kW + 100;
  for (int c = 0; c < 3; ++c) m.rgb[3 * texel + static_cast<std::size_t>(c)] = 1e5f;
  env::DetectionSettings s;
  s.source_count = 1;
  const auto d = env::detect_light_sources(m, s);
  print("one texel", d);
  ASSERT_EQ(d.sources.size(), 1u);
  // Within one texel (0.70 degrees) of the texel's centre; the texel itself is removed.
  EXPECT_LT(t::angle_deg(d.sources[0].direction, t::texel_direction(m, texel)), 0.71f);
  EXPECT_TRUE(std::binary_search(d.sources[0].texels.begin(), d.sources[0].texels.end(),
                                 static_cast<std::uint32_t>(texel)));
  const double share =
      t::luminous_energy(m, t::texel_direction(m, texel), 0.01f) / t::luminous_energy(m);
  EXPECT_GE(d.sources[0].energy_share, share);
  EXPECT_LT(d.sources[0].energy_share, share + 0.01);  // plus a few sky texels around it
}

TEST(LightSourceDetection, MoreSourcesRequestedThanBlobs) {
  auto m = t::flat_map(kW, kH, kSky);
  t::add_disc(m, t::dir_deg(120, 40), 3.0f, glm::vec3(2000));
  env::DetectionSettings s;
  s.source_count = 4;
  const auto d = env::detect_light_sources(m, s);
  print("4 requested, 1 blob", d);
  EXPECT_EQ(d.sources.size(), 1u);
  EXPECT_FALSE(d.stop.empty());
}

TEST(LightSourceDetection, AllBlackMapGivesNoSource) {
  const auto m = t::flat_map(kW, kH, glm::vec3(0));
  const auto d = env::detect_light_sources(m);
  EXPECT_TRUE(d.sources.empty());
  EXPECT_NE(d.stop.find("black"), std::string::npos) << d.stop;
}

// No bright region: a sky twice as bright at the zenith as at the nadir.
TEST(LightSourceDetection, NoBrightRegionGivesNoSource) {
  auto m = t::flat_map(kW, kH, kSky);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < 3; ++c)
        m.rgb[3 * (static_cast<std::size_t>(y) * kW + x) + static_cast<std::size_t>(c)] *=
            2.0f - static_cast<float>(y) / kH;
  const auto d = env::detect_light_sources(m);
  print("gradient sky", d);
  EXPECT_TRUE(d.sources.empty());
  EXPECT_NE(d.stop.find("min_contrast"), std::string::npos) << d.stop;
}

TEST(LightSourceDetection, NanAndInfiniteTexelsRejectedNamingTheMap) {
  PENUMBRA_STABILITY("NaN and infinite texels",
                     "std::invalid_argument naming the map, texel and channel", "-");
  auto m = t::flat_map(kW, kH, kSky, "bad_sky.exr");
  m.rgb[3 * (10 * kW + 20)] = std::numeric_limits<float>::quiet_NaN();
  try {
    env::detect_light_sources(m);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bad_sky.exr: texel (20, 10) channel R is NaN"),
              std::string::npos)
        << e.what();
  }
  m.rgb[3 * (10 * kW + 20)] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(env::detect_light_sources(m), std::invalid_argument);
}

TEST(LightSourceDetection, BadSettingsNameTheField) {
  PENUMBRA_STABILITY("source_count 0, halo percentile above the light percentile, ...",
                     "std::invalid_argument naming the field", "-");
  const auto m = t::flat_map(64, 32, kSky);
  env::DetectionSettings s;
  s.source_count = env::kMaxSources + 1;
  try {
    env::detect_light_sources(m, s);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("source_count"), std::string::npos) << e.what();
  }
  s = {};
  s.halo_percentile = 99.5f;  // above light_percentile
  EXPECT_THROW(env::detect_light_sources(m, s), std::invalid_argument);
  s = {};
  s.min_clusters = 0;
  EXPECT_THROW(env::detect_light_sources(m, s), std::invalid_argument);
}

// Maps smaller than the prefilter: the radius shrinks to fit, no error, no crash.
TEST(LightSourceDetection, TinyMapsDoNotFail) {
  PENUMBRA_STABILITY("maps smaller than the prefilter (1x1 up)",
                     "the radius shrinks to fit: no error, no crash", "-");
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{2, 1}, std::pair{3, 2}, std::pair{8, 4}}) {
    auto m = t::flat_map(w, h, kSky);
    for (int c = 0; c < 3; ++c) m.rgb[static_cast<std::size_t>(c)] = 1e4f;
    env::DetectionSettings s;
    s.source_count = env::kMaxSources;
    env::LightSourceDetection d;
    EXPECT_NO_THROW(d = env::detect_light_sources(m, s)) << w << "x" << h;
    EXPECT_LE(d.sources.size(), static_cast<std::size_t>(w * h));
  }
}

TEST(LightSourceDetection, Deterministic) {
  auto m = t::flat_map(kW, kH, kSky);
  t::add_disc(m, t::dir_deg(60, 35), 3.0f, glm::vec3(3000));
  t::add_disc(m, t::dir_deg(250, 10), 4.0f, glm::vec3(800));
  const auto a = env::detect_light_sources(m), b = env::detect_light_sources(m);
  ASSERT_EQ(a.sources.size(), b.sources.size());
  for (std::size_t i = 0; i < a.sources.size(); ++i) {
    EXPECT_EQ(a.sources[i].direction, b.sources[i].direction);
    EXPECT_EQ(a.sources[i].texels, b.sources[i].texels);
  }
}

// 003's own halo (nearest centroid) also finds a lone disc's direction, but splits the disc
// among the clusters around it: the radius and the share come out smaller.
TEST(LightSourceDetection, NearestCentroidHaloSplitsALoneDisc) {
  auto m = t::flat_map(kW, kH, kSky);
  const glm::vec3 sun = t::dir_deg(60, 35);
  t::add_disc(m, sun, 3.0f, glm::vec3(3000));
  env::DetectionSettings s;
  s.source_count = 1;
  s.halo_set = env::HaloSet::kNearestCentroid;
  const auto d = env::detect_light_sources(m, s);
  print("disc, 003 halo", d);
  ASSERT_EQ(d.sources.size(), 1u);
  EXPECT_LT(t::angle_deg(d.sources[0].direction, sun), 0.5f);
  const double share = t::luminous_energy(m, sun, 3.0f) / t::luminous_energy(m);
  EXPECT_LT(d.sources[0].energy_share, 0.9 * share);
}

}  // namespace
