// The EnvironmentLight resource's sources and OEM sets (environment_light_update.h).
#include "penumbra/systems/environment/environment_light_update.h"

#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <stdexcept>

#include "common/stability.h"
#include "penumbra/sh/projection.h"
#include "synthetic_maps.h"

namespace env = penumbra::environment;
namespace sh = penumbra::sh;
namespace t = penumbra::test;

namespace {

TEST(EnvironmentLightUpdate, FillsSourcesAndSetsLeavesRadianceAlone) {
  auto m = t::flat_map(512, 256, glm::vec3(0.3f, 0.4f, 0.6f));
  t::add_disc(m, t::dir_deg(60, 35), 3.0f, glm::vec3(3000));
  penumbra::components::EnvironmentLight light;
  light.map = std::make_shared<penumbra::data::EnvironmentMap>(m);
  light.radiance = sh::project_equirect<sh::kDefaultBands>(m.rgb.data(), m.width, m.height);
  light.version = 7;
  const auto radiance = light.radiance;
  EXPECT_TRUE(env::sources_stale(light));

  env::DetectionSettings s;
  s.source_count = 1;
  const auto d = env::update_environment_light(light, s);
  ASSERT_EQ(light.sources.size(), 1u);
  EXPECT_EQ(light.oem_sh.size(), 2u);
  EXPECT_EQ(light.oem_sh3.size(), 2u);
  EXPECT_EQ(light.version, 7u);
  EXPECT_FALSE(env::sources_stale(light));
  EXPECT_EQ(light.radiance, radiance);
  EXPECT_EQ(light.sources[0].direction, d.sources[0].direction);
  EXPECT_FLOAT_EQ(light.sources[0].energy_share, d.sources[0].energy_share);
  EXPECT_LT(t::angle_deg(light.sources[0].direction, t::dir_deg(60, 35)), 0.5f);
  // The whole-map set is the map's radiance SH.
  EXPECT_NEAR(light.oem_sh[1][1][0], radiance[1][0], 1e-3f * radiance[1][0]);  // float sums
}

TEST(EnvironmentLightUpdate, NullMapClears) {
  penumbra::components::EnvironmentLight light;
  light.sources.resize(2);
  light.oem_sh.resize(4);
  light.version = 3;
  env::update_environment_light(light);
  EXPECT_TRUE(light.sources.empty());
  EXPECT_TRUE(light.oem_sh.empty());
  EXPECT_EQ(light.sources_version, 3u);
}

TEST(EnvironmentLightUpdate, BadMapThrowsAndLeavesTheResource) {
  PENUMBRA_STABILITY("a bad map given to the update",
                     "std::invalid_argument; the resource keeps its sources", "-");
  auto m = t::flat_map(64, 32, glm::vec3(1), "inf.exr");
  m.rgb[5] = std::numeric_limits<float>::infinity();
  penumbra::components::EnvironmentLight light;
  light.map = std::make_shared<penumbra::data::EnvironmentMap>(m);
  light.sources.resize(1);
  EXPECT_THROW(env::update_environment_light(light), std::invalid_argument);
  EXPECT_EQ(light.sources.size(), 1u);
}

}  // namespace
