// Edge rays (probe_edge_rays.h, [Sukys14] sec. 3.2.2): probes where Delaunay edges cross
// geometry, on both sides of a wall, none in open space; the bake's rounds and determinism.
#include "penumbra/systems/probe_bake/probe_edge_rays.h"

#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/stability.h"
#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/systems/probe_bake/probe_bake.h"
#include "test_paths.h"

namespace penumbra::probe_bake {
namespace {

// Distance to the nearest surface along 26 directions (an upper bound of the true distance).
float surface_distance(const reference::Scene& traced, const glm::vec3& p) {
  float best = std::numeric_limits<float>::infinity();
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        if (!x && !y && !z) continue;
        best = std::min(best, traced.hit_distance(p, glm::normalize(glm::vec3(x, y, z)), 100.0f));
      }
  return best;
}

TEST(ProbeEdgeRays, OpenSpaceAddsNothing) {
  PENUMBRA_STABILITY("edge rays in open space", "no probe added", "-");
  const BakeScene s = parse_bake_scene(
      R"({"probes": {"min": [0,0,0], "max": [3,3,3], "spacing": 1}})", "open.json", kData);
  const reference::Scene traced(s.desc);
  EdgeRayStats st;
  EXPECT_TRUE(edge_ray_points(s, traced, grid_points(s.volume), {}, &st).empty());
  EXPECT_GT(st.edges, 0u);
  EXPECT_EQ(st.hits, 0u);
}

TEST(ProbeEdgeRays, ThinWallGetsProbesOnBothSides) {
  PENUMBRA_STABILITY("a 0.1 m wall between two grid columns (light leaking through a thin wall)",
                     "probes added on both sides of the wall, none inside", "--edge-rays");
  // A 0.1 m wall at x = 0 between grid columns x = -0.5 and x = +0.5; open space elsewhere.
  const BakeScene s = parse_bake_scene(
      R"({"geometry": [{"kind": "wall", "from": [0, -5], "to": [0, 5], "base": -5, "height": 10,
                        "thickness": 0.1}],
          "probes": {"min": [-1.5, -1, -1], "max": [1.5, 1, 1], "spacing": 1}})",
      "wall.json", kData);
  const reference::Scene traced(s.desc);
  EdgeRayStats st;
  const auto pts = edge_ray_points(s, traced, grid_points(s.volume), {}, &st);
  std::size_t minus = 0, plus = 0;
  for (const glm::vec3& q : pts) {
    EXPECT_FALSE(s.inside(q));
    EXPECT_LT(std::abs(q.x), 0.05f + 0.1f * 1.8f) << "within the offset of the wall";
    (q.x < 0 ? minus : plus) += 1;
  }
  EXPECT_GT(minus, 0u);
  EXPECT_EQ(minus, plus);  // the scene is symmetric: each ray has its mirror
  EXPECT_EQ(st.added, pts.size());
  // Edges between the wall's own columns do not cross it: no hit from x = -1.5 to -0.5.
  for (const glm::vec3& q : pts) EXPECT_GT(std::abs(q.x), 0.05f);
}

TEST(ProbeEdgeRays, RoomBothSidesOfTheInnerWallAndNoneInOpenSpace) {
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  const reference::Scene traced(s.desc);
  BakeSettings b;
  b.samples = 64;
  b.edge_rays.enabled = true;
  BakeReport r;
  const data::ProbeCloud c = bake_probe_cloud(s, traced, b, &r);
  EXPECT_TRUE(r.valid_cloud);
  EXPECT_GT(r.edge_added, 0u);
  EXPECT_GE(r.edge_rounds, 1);
  EXPECT_LE(r.edge_rounds, b.edge_rays.max_iterations);
  std::size_t dark = 0, lit = 0;
  for (const ProbeRecord& p : r.probes) {
    if (p.edge_round == 0) continue;
    EXPECT_FALSE(s.inside(p.position));
    // Every edge-ray probe is near a surface (offset <= 0.1 edge length; the longest edges of
    // the 1 m grid's tetrahedra are below 2.5 m), never in open space.
    EXPECT_LT(surface_distance(traced, p.position), 0.3f) << p.position.x << " " << p.position.y;
    if (p.position.y < 2 && std::abs(p.position.x) < 0.5f) (p.position.x > 0 ? dark : lit) += 1;
  }
  EXPECT_GT(dark, 0u);
  EXPECT_GT(lit, 0u);
  std::printf(
      "room 1 m: %zu edge-ray probes (%zu dark side, %zu lit side of the inner wall), "
      "%zu dropped, %d rounds, %zu edges, %zu hits\n",
      r.edge_added, dark, lit, r.edge_dropped, r.edge_rounds, r.edge.edges, r.edge.hits);
  // Deterministic: the same bytes again.
  EXPECT_EQ(assets::encode_probe_cloud_file(bake_probe_cloud(s, traced, b)),
            assets::encode_probe_cloud_file(c));
}

TEST(ProbeEdgeRays, RoundsCapped) {
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  const reference::Scene traced(s.desc);
  BakeSettings b;
  b.samples = 16;
  b.spacing = 2;
  b.edge_rays.enabled = true;
  b.edge_rays.max_iterations = 1;
  BakeReport one, three;
  bake_probe_cloud(s, traced, b, &one);
  EXPECT_EQ(one.edge_rounds, 1);
  b.edge_rays.max_iterations = 3;
  bake_probe_cloud(s, traced, b, &three);
  EXPECT_GE(three.edge_added, one.edge_added);
  EXPECT_LE(three.edge_rounds, 3);
}

}  // namespace
}  // namespace penumbra::probe_bake
