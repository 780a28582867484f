// The three-source map (three_source_map.h: studio.exr plus a 2.5-degree sun) under the
// detection with three sources requested: the sun and both lamps are found, the sun within 1
// degree of where it was put with a radius within a factor 2 of the disc's (the prefilter
// widens a 3.5-texel disc), each lamp within 2 degrees and a factor 1.5 in radius of what the
// detection finds on studio.exr alone, and the sun carries at least 80% of the energy added.
#include "three_source_map.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "penumbra/assets/exr.h"
#include "penumbra/systems/environment/light_source_detection.h"

namespace env = penumbra::environment;
namespace t = penumbra::test;
namespace ts = penumbra::test::three_sources;

namespace {

penumbra::data::EnvironmentMap studio() {
  return penumbra::assets::load_environment_map(std::filesystem::path(PENUMBRA_SHARED_DATA) /
                                                "hdri" / "studio.exr");
}

// The found source nearest `dir`, or nullptr when none was found.
const env::DetectedSource* nearest(const env::LightSourceDetection& d, glm::vec3 dir) {
  const env::DetectedSource* best = nullptr;
  for (const auto& s : d.sources)
    if (!best || t::angle_deg(s.direction, dir) < t::angle_deg(best->direction, dir)) best = &s;
  return best;
}

TEST(ThreeSourceMap, DetectionFindsTheSunAndBothLamps) {
  const penumbra::data::EnvironmentMap base = studio();
  const penumbra::data::EnvironmentMap m = ts::add_sun(base);
  env::DetectionSettings s;
  s.source_count = 3;
  const env::LightSourceDetection d = env::detect_light_sources(m, s);
  for (const auto& src : d.sources)
    std::printf("  az %.2f el %.2f radius %.2f deg share %.2f%%\n",
                static_cast<double>(src.azimuth_deg), static_cast<double>(src.elevation_deg),
                static_cast<double>(src.angular_radius / t::kDeg),
                static_cast<double>(100 * src.energy_share));
  ASSERT_EQ(d.sources.size(), 3u) << d.stop;

  const env::DetectedSource* sun = nearest(d, ts::sun_direction());
  ASSERT_NE(sun, nullptr);
  EXPECT_LT(t::angle_deg(sun->direction, ts::sun_direction()), 1.0f);
  const float sun_radius = sun->angular_radius / t::kDeg;
  EXPECT_GT(sun_radius, ts::kSunRadiusDeg / 2);
  EXPECT_LT(sun_radius, ts::kSunRadiusDeg * 2);
  // The removed texels hold the disc (it is inside the sun's core), so its energy is taken out.
  const double added = t::luminous_energy(m) - t::luminous_energy(base);
  EXPECT_GT(sun->energy_share * t::luminous_energy(m), 0.8 * added);

  for (const ts::Lamp& lamp : ts::kStudioLamps) {
    const glm::vec3 dir = t::dir_deg(lamp.azimuth_deg, lamp.elevation_deg);
    const env::DetectedSource* found = nearest(d, dir);
    ASSERT_NE(found, nullptr);
    EXPECT_NE(found, sun);
    EXPECT_LT(t::angle_deg(found->direction, dir), 2.0f) << lamp.azimuth_deg;
    EXPECT_GT(found->angular_radius / t::kDeg, lamp.radius_deg / 1.5f) << lamp.azimuth_deg;
    EXPECT_LT(found->angular_radius / t::kDeg, lamp.radius_deg * 1.5f) << lamp.azimuth_deg;
  }
}

// The map is built the same way every time (the bench and this test share it).
TEST(ThreeSourceMap, Deterministic) {
  const penumbra::data::EnvironmentMap a = ts::add_sun(studio()), b = ts::add_sun(studio());
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_NE(a.rgb, studio().rgb);
}

}  // namespace
