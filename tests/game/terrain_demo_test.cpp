// The main job's scene without the renderer: the demo's systems animate the sky and the light,
// edit the terrain on schedule, and the terrain shadow system follows; the debug view draws
// the probed texel's horizon fan.
#include "penumbra/game/terrain_demo.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "common/stability.h"
#include "penumbra/assets/load_error.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/receiver.h"
#include "penumbra/components/receiver_lighting.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/spherical_light.h"
#include "penumbra/components/terrain.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/height_field.h"
#include "penumbra/game/boulders.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/render/packet.h"
#include "penumbra/systems/blocker_accumulation/blocker_systems.h"

namespace penumbra::game {
namespace {

using components::SphericalLight;
using components::Terrain;
using components::TerrainLighting;

TEST(TerrainDemo, SkyLightAndEditsDriveTheShadowSystem) {
  ecs::World world;
  TerrainDemoConfig config;
  config.terrain_size = 64;     // a crop of the DEM: the same code path, less work
  config.probes.count = 0;      // the probe cloud has its own tests (probe_demo_test.cpp)
  config.edit_interval = 0.1f;  // every 3 frames of 1/30 s
  populate_terrain_demo(world, config);
  jobs::Schedule schedule;
  add_terrain_demo_systems(schedule, config);
  jobs::Executor executor(2);

  executor.run(schedule, world);
  const auto first_heights = [&] {
    std::shared_ptr<const data::HeightField> h;
    world.query<const Terrain>().each([&](const Terrain& t) { h = t.heights; });
    return h;
  }();
  glm::vec3 light_before{};
  world.query<const SphericalLight>().each(
      [&](const SphericalLight& l) { light_before = l.position; });
  for (int f = 0; f < 6; ++f) executor.run(schedule, world);

  int terrains = 0;
  world.query<const Terrain, const TerrainLighting>().each(
      [&](const Terrain& t, const TerrainLighting& l) {
        ++terrains;
        EXPECT_EQ(t.version, 2u) << "edits at frames 3 and 6";
        EXPECT_NE(t.heights, first_heights);
        ASSERT_TRUE(l.rgb);
        EXPECT_EQ(l.width, 64);
        EXPECT_EQ(l.rgb->size(), 64u * 64u);
        for (const glm::vec3& c : *l.rgb) ASSERT_TRUE(std::isfinite(c.x) && c.x >= 0);
      });
  EXPECT_EQ(terrains, 1);
  world.query<const SphericalLight>().each(
      [&](const SphericalLight& l) { EXPECT_NE(l.position, light_before); });
  EXPECT_GT(world.resource<components::EnvironmentLight>().rotation_z, 0.0f);
  const render::RenderPacket& packet = world.resource<render::RenderPacket>();
  EXPECT_EQ(packet.spheres.size(), 1u) << "the light";
  // The horizon fan of the view-centre texel: one ray and one rim segment per azimuth, and
  // the normal.
  EXPECT_EQ(packet.lines.size(), 2u * 32u + 1u);
  // The renderer gets the heights times the demo's vertical exaggeration.
  ASSERT_TRUE(packet.terrain.heights);
  world.query<const Terrain>().each([&](const Terrain& t) {
    EXPECT_EQ(t.height_scale, 2.0f);
    EXPECT_FLOAT_EQ(packet.terrain.heights->at(5, 7), t.height_scale * t.heights->at(5, 7));
  });
}

// The boulders are drawn and shaded from simplified meshes (BoulderConfig::simplify_error): a
// tenth of the triangles at most, their vertices the receivers; 0 keeps the full meshes.
TEST(TerrainDemo, BouldersUseSimplifiedMeshesUnlessAskedNotTo) {
  const auto triangles = [](float simplify_error) {
    ecs::World world;
    TerrainDemoConfig config;
    config.terrain_size = 65;
    config.edit_interval = 0;
    config.probes.count = 0;
    config.boulders.count = 3;  // bunny, bunny, Suzanne
    config.boulders.spheres = 8;
    config.boulders.simplify_error = simplify_error;
    config.boulders.cache_dir =
        (std::filesystem::temp_directory_path() / "penumbra_boulders_test").string();
    populate_terrain_demo(world, config);
    std::size_t n = 0;
    world.query<const Boulder, const components::MeshInstance, const components::Receiver>().each(
        [&](const Boulder&, const components::MeshInstance& m, const components::Receiver& r) {
          n += m.mesh->indices.size() / 3;
          EXPECT_EQ(r.points->size(), m.mesh->positions.size());  // its vertices receive
        });
    return n;
  };
  const std::size_t full = triangles(0.0f), simplified = triangles(0.01f);
  EXPECT_EQ(full, 2u * 5648 + 14842);          // bunny 5,648, Suzanne 14,842 triangles
  EXPECT_LE(simplified, full / 10 + 2 * 100);  // the bunny stops at its error bound (636)
  EXPECT_GT(simplified, 0u);
}

// The rolling boulders: fitted sphere sets (cached as sphere files), rolling on the ground,
// shaded, and shadowing the terrain under them.
TEST(TerrainDemo, BouldersRollShadeAndShadowTheTerrain) {
  ecs::World world;
  TerrainDemoConfig config;
  config.terrain_size = 129;
  config.edit_interval = 0;
  config.probes.count = 0;
  config.boulders.count = 3;
  config.boulders.spheres = 8;
  config.boulders.radius = 400;
  const std::filesystem::path cache =
      std::filesystem::temp_directory_path() / "penumbra_boulders_test";
  std::filesystem::remove_all(cache);
  config.boulders.cache_dir = cache.string();
  populate_terrain_demo(world, config);
  EXPECT_TRUE(std::filesystem::exists(cache / "bunny_8.psph"));
  EXPECT_TRUE(std::filesystem::exists(cache / "suzi_8.psph"));
  world.resource<blocker_accumulation::BlockerSettingsResource>().refresh_period = 1;
  world.resource<blocker_accumulation::BlockerSettingsResource>().receiver_budget = 0;
  jobs::Schedule schedule;
  add_terrain_demo_systems(schedule, config);
  jobs::Executor executor(2);
  std::vector<glm::vec3> first;
  int boulders = 0;
  for (int f = 0; f < 4; ++f) executor.run(schedule, world);
  world.query<const Boulder, const components::Transform, const components::ReceiverLighting>()
      .each([&](const Boulder& b, const components::Transform& t,
                const components::ReceiverLighting& l) {
        ++boulders;
        ASSERT_NE(l.irradiance, nullptr);
        for (const glm::vec3& e : *l.irradiance) ASSERT_TRUE(std::isfinite(e.x));
        first.push_back(glm::vec3(t.world[3]));
        EXPECT_GT(b.radius, 0.0f);
      });
  EXPECT_EQ(boulders, 3);
  EXPECT_TRUE(world.resource<blocker_accumulation::BlockerField>().errors.empty());
  // Some terrain texels are darker than the terrain system's own lighting: the boulders' shadow.
  int shadowed = 0;
  world.query<const blocker_accumulation::BlockerTerrainState>().each(
      [&](const blocker_accumulation::BlockerTerrainState& s) {
        for (const glm::vec3& r : s.ratio) shadowed += r.x < 0.95f;
      });
  EXPECT_GT(shadowed, 0);
  for (int f = 0; f < 10; ++f) executor.run(schedule, world);
  int moved = 0, k = 0;
  world.query<const Boulder, const components::Transform>().each(
      [&](const Boulder&, const components::Transform& t) {
        moved += glm::length(glm::vec3(t.world[3]) - first[static_cast<std::size_t>(k++)]) > 1.0f;
      });
  EXPECT_EQ(moved, 3);
  // The debug view: each sphere as three wire circles of 16 segments, only when asked for.
  world.resource<BoulderView>().spheres = true;
  executor.run(schedule, world);
  std::size_t lines = 0;
  world.query<const Boulder, const components::DebugLines>().each(
      [&](const Boulder&, const components::DebugLines& d) { lines += d.lines.size(); });
  EXPECT_EQ(lines, 3u * 8 * 3 * 16);
  // A second start loads the cached sets instead of fitting again.
  ecs::World again;
  populate_terrain_demo(again, config);
  std::filesystem::remove_all(cache);
}

TEST(TerrainDemo, MissingDataNamesTheFile) {
  PENUMBRA_STABILITY("a missing data folder", "an error naming the file", "-");
  ecs::World world;
  TerrainDemoConfig config;
  config.data_dir = "/nonexistent/penumbra-data";
  try {
    populate_terrain_demo(world, config);
    FAIL() << "loaded from a missing folder";
  } catch (const assets::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("jacksboro_fault_dem"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::game
