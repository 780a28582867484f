// The valley game's canyon (valley_canyon.h): the carve, the probes along it, the arches.
#include "penumbra/game/valley_canyon.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "penumbra/components/mesh.h"
#include "penumbra/components/sphere_set.h"
#include "penumbra/components/terrain.h"

namespace penumbra::game {
namespace {

// A flat 12.8 km field of 100 m cells at height 500 m (field units, scale 2: 1,000 m).
data::HeightField flat() {
  data::HeightField f;
  f.width = f.height = 129;
  f.cell_size = 100.0f;
  f.heights.assign(129 * 129, 500.0f);
  return f;
}

TEST(ValleyCanyon, TheCarveIsFullDepthOnTheAxisAndLeavesTheLandAway) {
  data::HeightField f = flat();
  const glm::vec3 origin(-6400.0f, -6400.0f, 0.0f);
  CanyonConfig c;
  c.from = {-0.4f, 0.0f};
  c.to = {0.4f, 0.0f};
  carve_canyon(f, origin, 2.0f, c);
  // On the axis (y = 0: row 64) the world height is 1,000 - depth; 2 x half width away, untouched.
  EXPECT_NEAR(2.0f * f.at(64, 64), 1000.0f - c.depth, 1e-3f);
  EXPECT_NEAR(2.0f * f.at(64, 64 + 9), 1000.0f, 1e-3f);  // 900 m > 2 x 420
  const float side = 2.0f * f.at(64, 64 + 6);            // 600 m: part way up the wall
  EXPECT_GT(side, 1000.0f - c.depth);
  EXPECT_LT(side, 1000.0f);
  EXPECT_NEAR(2.0f * f.at(2, 64), 1000.0f, 1e-3f);  // beyond the axis' end
  for (float h : f.heights) ASSERT_TRUE(std::isfinite(h));
}

TEST(ValleyCanyon, ProbesFollowTheFloorAtTheirHeights) {
  CanyonConfig c;
  const std::vector<glm::vec3> probes = canyon_probes(12800.0f, c);
  ASSERT_GE(probes.size(), 2 * c.probe_heights.size());
  EXPECT_EQ(probes.size() % c.probe_heights.size(), 0u);
  EXPECT_EQ(glm::vec2(probes.front()), c.from);
  EXPECT_NEAR(probes.back().x, c.to.x, 1e-6f);
  EXPECT_NEAR(probes.back().y, c.to.y, 1e-6f);
  EXPECT_EQ(probes[0].z, c.probe_heights[0]);
  EXPECT_EQ(probes[1].z, c.probe_heights[1]);
}

TEST(ValleyCanyon, AnArchsSpheresHoldItsSurface) {
  const ArchShape arch = make_arch({100.0f, 200.0f, 50.0f}, glm::vec2(1.0f, 0.0f), 500.0f, 80.0f);
  ASSERT_FALSE(arch.mesh->positions.empty());
  EXPECT_EQ(arch.mesh->normals.size(), arch.mesh->positions.size());
  EXPECT_EQ(arch.mesh->indices.size() % 3, 0u);
  for (std::uint32_t i : arch.mesh->indices) ASSERT_LT(i, arch.mesh->positions.size());
  float top = -1e30f;
  for (std::size_t i = 0; i < arch.mesh->positions.size(); ++i) {
    const glm::vec3 p = arch.mesh->positions[i];
    EXPECT_NEAR(glm::length(arch.mesh->normals[i]), 1.0f, 1e-4f);
    top = std::max(top, p.z);
    // Every surface point lies within a blocker sphere or a tenth of the thickness from one:
    // the blocker system sees the arch the renderer draws.
    float gap = std::numeric_limits<float>::max();
    for (const data::Sphere& s : *arch.spheres)
      gap = std::min(gap, glm::length(p - s.centre) - s.radius);
    ASSERT_LT(gap, 0.1f * 80.0f) << "vertex " << i;
  }
  EXPECT_NEAR(top, 50.0f + 500.0f + 80.0f, 1.0f);
  // It spans across the axis (x): its feet are 500 m either side in y.
  float y_lo = 1e30f, y_hi = -1e30f;
  for (const glm::vec3& p : arch.mesh->positions)
    y_lo = std::min(y_lo, p.y), y_hi = std::max(y_hi, p.y);
  EXPECT_NEAR(y_hi - y_lo, 2 * (500.0f + 80.0f), 2.0f);
}

TEST(ValleyCanyon, ArchesStandInTheCarvedCanyon) {
  ecs::World world;
  auto f = std::make_shared<data::HeightField>(flat());
  const glm::vec3 origin(-6400.0f, -6400.0f, 0.0f);
  CanyonConfig c;
  carve_canyon(*f, origin, 2.0f, c);
  world.create_with(components::Terrain{f, origin, glm::vec3(0.5f), 2.0f});
  add_canyon_arches(world, c);
  int arches = 0;
  world.query<const components::MeshInstance, const components::SphereSet>().each(
      [&](const components::MeshInstance& m, const components::SphereSet& s) {
        ++arches;
        float lowest = 1e30f;
        for (const glm::vec3& p : m.mesh->positions) lowest = std::min(lowest, p.z);
        // The feet stand on the floor (1,000 m - depth).
        EXPECT_NEAR(lowest, 1000.0f - c.depth, 1.0f);
        EXPECT_FALSE(s.spheres->empty());
      });
  EXPECT_EQ(arches, c.arches);
  ecs::World bare;
  add_canyon_arches(bare, c);  // no terrain: nothing, no crash
  EXPECT_EQ(bare.size(), 0u);
}

}  // namespace
}  // namespace penumbra::game
