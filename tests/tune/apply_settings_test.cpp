// The apply step (game/tune/apply_settings.h): a settings file's values reach the systems'
// settings structs and, for the systems it tuned only, the world's settings resources.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "penumbra/ecs/world.h"
#include "penumbra/systems/blocker_accumulation/blocker_systems.h"
#include "penumbra/systems/spherical_lights/spherical_light_systems.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"
#include "tune/apply_settings.h"

namespace penumbra::tune {
namespace {

settings::TunedSettings tuned() {
  settings::TunedSettings s;
  s.scene = std::string("t");
  s.terrain.horizon = std::string("march");  // not = "march": GCC 12 -Wrestrict (bug 105329)
  s.terrain.level_step = 2;
  s.terrain.azimuths = 8;
  s.terrain.bands = 3;
  s.terrain.result.tuned = true;
  s.blockers.epsilon = 0.3f;
  s.blockers.spheres_per_object = 32;
  s.blockers.result.tuned = true;
  s.probes.probes_per_side = 6;
  s.probes.result.tuned = true;
  s.spherical_lights.blocking = std::string("per_object");  // not tuned: must not be applied
  return s;
}

TEST(ApplySettings, SystemStructs) {
  const SystemSettings o = system_settings(tuned());
  EXPECT_EQ(o.terrain.method, terrain_shadow::HorizonMethod::kMarch);
  EXPECT_EQ(o.terrain.azimuths, 8);
  EXPECT_EQ(o.terrain.pyramid.level_step, 2);
  EXPECT_EQ(o.terrain_bands, 3);
  EXPECT_FLOAT_EQ(o.blockers.blocker.epsilon, 0.3f);
  EXPECT_EQ(o.spheres_per_object, 32);
  EXPECT_EQ(o.probes_per_side, 6);
}

TEST(ApplySettings, LoadsFromAFile) {
  const auto file = std::filesystem::temp_directory_path() / "penumbra_apply_test.settings";
  settings::save_settings(file, tuned());
  EXPECT_EQ(load_system_settings(file).terrain.azimuths, 8);
  std::filesystem::remove(file);
}

TEST(ApplySettings, WorldResourcesOfTunedSystemsOnly) {
  ecs::World world;
  terrain_shadow::emplace_terrain_shadow_resources(world);
  blocker_accumulation::emplace_blocker_resources(world);
  spherical_lights::emplace_spherical_light_resources(world);
  const float min_sin =
      world.resource<blocker_accumulation::BlockerSettingsResource>().settings.blocker.min_sin;
  apply_to_world(system_settings(tuned()), world);
  const auto& t = world.resource<terrain_shadow::TerrainShadowSettings>().config;
  EXPECT_EQ(t.method, terrain_shadow::HorizonMethod::kMarch);
  EXPECT_EQ(t.azimuths, 8);
  const auto& b = world.resource<blocker_accumulation::BlockerSettingsResource>().settings;
  EXPECT_FLOAT_EQ(b.blocker.epsilon, 0.3f);
  EXPECT_FLOAT_EQ(b.blocker.min_sin, min_sin);  // untouched
  EXPECT_EQ(world.resource<spherical_lights::SphericalLightSettingsResource>().settings.blocking,
            spherical_lights::SlBlocking::kPerSphere);  // not tuned: the default stays
}

}  // namespace
}  // namespace penumbra::tune
