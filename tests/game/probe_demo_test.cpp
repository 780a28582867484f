// The probe cloud in the main job (probe_demo.h): the demo builds a valid cloud over the terrain,
// its floating objects find a cell every frame and are shaded from it (brighter on a lit slope
// than in a shadowed valley), the cloud follows the turning sky, and the debug views draw only
// when asked for.
#include "penumbra/game/probe_demo.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "common/stability.h"
#include "penumbra/components/debug_shapes.h"
#include "penumbra/components/environment_light.h"
#include "penumbra/components/lighting_result.h"
#include "penumbra/components/mesh.h"
#include "penumbra/components/probe_anchor.h"
#include "penumbra/components/probe_cloud_resource.h"
#include "penumbra/components/probe_lighting.h"
#include "penumbra/components/transform.h"
#include "penumbra/data/mesh.h"
#include "penumbra/game/terrain_demo.h"
#include "penumbra/jobs/executor.h"
#include "penumbra/render/packet.h"
#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"
#include "penumbra/systems/probe_cloud/probe_systems.h"

namespace penumbra::game {
namespace {

using components::DebugLines;
using components::ProbeAnchor;
using components::ProbeCloudResource;
using components::ProbeLighting;
using components::Transform;
using components::VertexLighting;

TerrainDemoConfig small_config() {
  TerrainDemoConfig config;
  config.terrain_size = 129;
  config.edit_interval = 0;
  config.boulders.count = 0;
  config.probes.count = 3;
  config.probes.grid = 8;
  config.probes.sky_steps = 32;
  config.probes.samples = 32;
  return config;
}

double luminance(const glm::vec3& c) {
  return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

// Mean luminance of an object's vertex lighting; every value finite and >= 0, some > 0.
double mean_lighting(const VertexLighting& l, std::size_t vertices) {
  EXPECT_TRUE(l.rgb);
  if (!l.rgb) return 0;
  EXPECT_EQ(l.rgb->size(), vertices);
  double sum = 0;
  for (const glm::vec3& c : *l.rgb) {
    EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
    EXPECT_GE(std::min({c.x, c.y, c.z}), 0.0f);
    sum += luminance(c);
  }
  return sum / static_cast<double>(l.rgb->size());
}

TEST(ProbeDemo, ObjectsFindTheirCellAndTheDebugViewDrawsOnlyWhenOn) {
  ecs::World world;
  const TerrainDemoConfig config = small_config();
  populate_terrain_demo(world, config);
  const auto cloud = world.resource<ProbeCloudResource>().cloud;
  ASSERT_TRUE(cloud);
  EXPECT_EQ(cloud->probe_count(), 8u * 8u * 3u);
  EXPECT_EQ(cloud->bands, 3);
  EXPECT_GT(cloud->inner_count, 0u);
  const probe_cloud::ProbeCloudValidation v = probe_cloud::validate_probe_cloud(*cloud);
  EXPECT_TRUE(v.ok()) << (v.errors.empty() ? "" : v.errors.front());
  std::printf("probe demo start-up (8 x 8 x 3 probes, 32 x 16 sky cells): %.3f s\n",
              world.resource<ProbeSkyBake>().startup_seconds);

  jobs::Schedule schedule;
  add_terrain_demo_systems(schedule, config);
  jobs::Executor executor(2);
  executor.run(schedule, world);
  const std::uint64_t generation = world.resource<probe_cloud::ProbeWalkState>().generation;
  EXPECT_GT(generation, 0u);
  int objects = 0;
  world
      .query<const ProbeFloater, const ProbeAnchor, const ProbeLighting, const VertexLighting,
             const components::MeshInstance>()
      .each([&](const ProbeFloater&, const ProbeAnchor& a, const ProbeLighting& l,
                const VertexLighting& vl, const components::MeshInstance& m) {
        ++objects;
        EXPECT_GE(a.cell, 0);
        EXPECT_LT(static_cast<std::size_t>(a.cell), cloud->cells.size());
        EXPECT_EQ(a.generation, generation);
        EXPECT_TRUE(l.valid);
        EXPECT_GT(mean_lighting(vl, m.mesh->positions.size()), 0.0);
        EXPECT_LT(m.mesh->indices.size() / 3, 3000u) << "simplified, as the boulders";
      });
  EXPECT_EQ(objects, 3);
  EXPECT_TRUE(world.resource<probe_cloud::ProbeWalkReport>().errors.empty());

  // Off (the default): the probe views add no line (the packet holds only the horizon fan).
  const auto probe_lines = [&] {
    std::size_t n = 0;
    world.query<const ProbeCloudView, const DebugLines>().each(
        [&](const ProbeCloudView&, const DebugLines& d) { n += d.lines.size(); });
    world.query<const ProbeWalkTrace, const DebugLines>().each(
        [&](const ProbeWalkTrace&, const DebugLines& d) { n += d.lines.size(); });
    return n;
  };
  EXPECT_EQ(probe_lines(), 0u);
  const std::size_t off_lines = world.resource<render::RenderPacket>().lines.size();
  EXPECT_EQ(off_lines, 2u * 32u + 1u);

  world.resource<ProbeDebugView>().enabled = true;
  executor.run(schedule, world);
  std::size_t sphere_lines = 0, cell_lines = 0;
  world.query<const ProbeCloudView, const DebugLines>().each(
      [&](const ProbeCloudView&, const DebugLines& d) { sphere_lines += d.lines.size(); });
  world.query<const ProbeWalkTrace, const DebugLines>().each(
      [&](const ProbeWalkTrace&, const DebugLines& d) {
        EXPECT_GE(d.lines.size(), 6u) << "an inner cell's 6 edges or an outer cell's 3 + 3";
        cell_lines += d.lines.size();
      });
  EXPECT_EQ(sphere_lines, cloud->probe_count() * 3u * 8u) << "three 8-segment circles per probe";
  EXPECT_EQ(world.resource<render::RenderPacket>().lines.size(),
            off_lines + sphere_lines + cell_lines);

  world.resource<ProbeDebugView>().enabled = false;
  executor.run(schedule, world);
  EXPECT_EQ(probe_lines(), 0u);
  EXPECT_EQ(world.resource<render::RenderPacket>().lines.size(), off_lines);
}

// An object held at the brightest and at the darkest probe of the lowest layer (120 m over the
// ground): at a probe the walk gives that probe's SH exactly, and the object's lighting follows.
TEST(ProbeDemo, ObjectIsBrighterOnALitSlopeThanInAShadowedValley) {
  ecs::World world;
  TerrainDemoConfig config = small_config();
  config.probes.count = 1;
  config.probes.sky_steps = 32;  // the demo's
  config.sky_rotation_speed = 0;
  populate_terrain_demo(world, config);
  const auto cloud = world.resource<ProbeCloudResource>().cloud;
  ASSERT_TRUE(cloud);
  const std::size_t n = 9;
  std::size_t bright = 0, dark = 0;
  double lo = 1e30, hi = -1;
  for (std::size_t p = 0; p < cloud->probe_count(); ++p) {
    // The lowest layer: no probe straight under it (the grid's columns share x and y).
    bool lowest = true;
    for (const glm::vec3& q : cloud->positions)
      lowest = lowest && !(q.x == cloud->positions[p].x && q.y == cloud->positions[p].y &&
                           q.z < cloud->positions[p].z);
    if (!lowest) continue;
    const float* s = cloud->probe_sh(p);
    const double dc = luminance({s[0], s[n], s[2 * n]});
    if (dc > hi) hi = dc, bright = p;
    if (dc < lo) lo = dc, dark = p;
  }
  ecs::Entity object{};
  world.query<const ProbeFloater>().each([&](ecs::Entity e, const ProbeFloater&) { object = e; });
  world.remove<ProbeFloater>(object);  // held in place by the test
  jobs::Schedule schedule;
  add_terrain_demo_systems(schedule, config);
  jobs::Executor executor(2);
  const auto lighting_at = [&](std::size_t probe) {
    world.get_mut<Transform>(object)->world =
        glm::scale(glm::translate(glm::mat4(1.0f), cloud->positions[probe]), glm::vec3(100.0f));
    executor.run(schedule, world);
    const std::size_t vertices =
        world.get<components::MeshInstance>(object)->mesh->positions.size();
    EXPECT_GE(world.get<ProbeAnchor>(object)->cell, 0);
    return mean_lighting(*world.get<VertexLighting>(object), vertices);
  };
  const double lit = lighting_at(bright), shadowed = lighting_at(dark);
  std::printf(
      "object lighting: lit %.4g at (%.0f, %.0f, %.0f), shadowed %.4g at (%.0f, %.0f, "
      "%.0f): ratio %.2f\n",
      lit, cloud->positions[bright].x, cloud->positions[bright].y, cloud->positions[bright].z,
      shadowed, cloud->positions[dark].x, cloud->positions[dark].y, cloud->positions[dark].z,
      lit / shadowed);
  EXPECT_GT(shadowed, 0.0);
  EXPECT_GT(lit, 1.5 * shadowed);  // measured 3.6 (129-sample crop, 8 x 8 x 3 probes)
  // The sky's intensity (the valley game's dusk) scales the probe-lit object with it.
  world.resource<components::EnvironmentLight>().intensity = 0.5f;
  EXPECT_NEAR(lighting_at(bright), 0.5 * lit, 1e-4 * lit);
}

// A turning sky re-projects the probes' SH (a new cloud, a new walk generation) and the objects
// locate afresh in it.
TEST(ProbeDemo, TurningSkyReplacesTheCloudAndObjectsFollow) {
  ecs::World world;
  TerrainDemoConfig config = small_config();
  config.sky_rotation_speed = 6.0f;  // 0.2 rad per frame: a 32-cell sky's step is 0.196
  populate_terrain_demo(world, config);
  jobs::Schedule schedule;
  add_terrain_demo_systems(schedule, config);
  jobs::Executor executor(2);
  executor.run(schedule, world);
  const auto first = world.resource<ProbeCloudResource>().cloud;
  for (int f = 0; f < 3; ++f) executor.run(schedule, world);
  const ProbeSkyBake& bake = world.resource<ProbeSkyBake>();
  EXPECT_GE(bake.bakes, 3u);
  const auto now = world.resource<ProbeCloudResource>().cloud;
  ASSERT_TRUE(now);
  EXPECT_NE(now, first);
  EXPECT_EQ(now->cells.size(), first->cells.size());
  EXPECT_NE(now->sh, first->sh);
  const std::uint64_t generation = world.resource<probe_cloud::ProbeWalkState>().generation;
  world.query<const ProbeFloater, const ProbeAnchor>().each(
      [&](const ProbeFloater&, const ProbeAnchor& a) {
        EXPECT_GE(a.cell, 0);
        EXPECT_EQ(a.generation, generation);
      });
}

TEST(ProbeDemo, NoObjectsNoCloud) {
  PENUMBRA_STABILITY("the demo with 0 probe objects",
                     "no cloud built; the probe debug view draws nothing", "-");
  ecs::World world;
  TerrainDemoConfig config = small_config();
  config.probes.count = 0;
  populate_terrain_demo(world, config);
  EXPECT_FALSE(world.resource<ProbeCloudResource>().cloud);
  jobs::Schedule schedule;
  add_terrain_demo_systems(schedule, config);
  jobs::Executor executor(2);
  executor.run(schedule, world);
  world.resource<ProbeDebugView>().enabled = true;
  executor.run(schedule, world);
  EXPECT_EQ(world.resource<render::RenderPacket>().lines.size(), 2u * 32u + 1u);
}

}  // namespace
}  // namespace penumbra::game
