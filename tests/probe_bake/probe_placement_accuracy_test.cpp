// Placement accuracy in the room (docs/probe_bake.md, "Edge rays" and "Error versus probe
// count"): relative RMS error of the interpolated irradiance against the reference integrator
// (direct + one bounce) at random free points, and the leak metric (points within 1 m of the
// inner wall on its dark side), per placement method. Prints the tables of the docs.
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/random_draws.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/probe_bake/probe_bake.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"
#include "room_accuracy_points.h"
#include "test_paths.h"

namespace penumbra::probe_bake {
namespace {

using accuracy::PointSet;
using accuracy::reference_values;
using accuracy::set_error;

// The room, its reference scene and three point sets with reference irradiance, made once.
class RoomAccuracy : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = std::make_unique<BakeScene>(load_bake_scene(kRoot / "scenes" / "room.json", kData));
    traced_ = std::make_unique<reference::Scene>(scene_->desc);
    // The same points as ProbeBakeAccuracy.RoomErrorVersusSpacing (room_accuracy_points.h).
    const auto sets = accuracy::room_point_sets(*scene_, *traced_);
    for (int i = 0; i < 3; ++i) sets_[i] = sets[static_cast<std::size_t>(i)];
  }
  static void TearDownTestSuite() {
    traced_.reset();
    scene_.reset();
  }

  static double error(const data::ProbeCloud& cloud, int set) {
    return set_error(cloud, sets_[set]);
  }

  static std::unique_ptr<BakeScene> scene_;
  static std::unique_ptr<reference::Scene> traced_;
  static PointSet sets_[3];  // free space, dark side of the inner wall, lit side
};
std::unique_ptr<BakeScene> RoomAccuracy::scene_;
std::unique_ptr<reference::Scene> RoomAccuracy::traced_;
PointSet RoomAccuracy::sets_[3];

// Edge rays ([Sukys14] sec. 3.2.2) against the leak: grid at three spacings, validity off / on,
// edge rays off / on.
TEST_F(RoomAccuracy, EdgeRaysLeak) {
  std::printf(
      "spacing validity edge_rays probes added dropped rounds | rel_rms  dark   lit | bake_s\n");
  for (float spacing : {2.0f, 1.5f, 1.0f, 0.5f}) {
    double leak[2][2] = {};
    for (int validity = 0; validity < 2; ++validity)
      for (int edge = 0; edge < 2; ++edge) {
        BakeSettings b;
        b.spacing = spacing;
        b.samples = 512;
        b.validity = validity;
        b.edge_rays.enabled = edge;
        BakeReport r;
        const data::ProbeCloud c = bake_probe_cloud(*scene_, *traced_, b, &r);
        EXPECT_TRUE(r.valid_cloud);
        const double e[3] = {error(c, 0), error(c, 1), error(c, 2)};
        leak[validity][edge] = e[1];
        std::printf("%-7g %-8s %-9s %6zu %5zu %7zu %6d | %7.3f %6.3f %5.3f | %6.2f\n",
                    double(spacing), validity ? "on" : "off", edge ? "on" : "off", c.probe_count(),
                    r.edge_added, r.edge_dropped, r.edge_rounds, e[0], e[1], e[2], r.total_seconds);
        std::fflush(stdout);
      }
    // Validity keeps the dark side dark (moves perpendicular to the exit face, inside the
    // grid's box; it was 18-86x before): within 0.5 at 1 and 0.5 m. Edge rays lower the leak
    // at 2 m (4.2 -> 1.9) and change it by under 10% where it is already at the noise.
    // At 1.5 m no grid column lies in the wall: tetrahedra cross it, the case edge rays are for.
    if (spacing <= 1) {
      EXPECT_LT(leak[1][0], 0.5) << "spacing " << spacing;
    } else {
      EXPECT_LT(leak[1][1], 0.7 * leak[1][0]) << "spacing " << spacing;
    }
    EXPECT_LT(leak[1][1], 1.1 * leak[1][0]) << "spacing " << spacing;
  }
}

}  // namespace
}  // namespace penumbra::probe_bake
namespace penumbra::probe_bake {
namespace {
// Error versus probe count per placement method (docs/probe_bake.md): uniform grids at five
// spacings, spawn and merge, gradient ascent; validity on, edge rays off, 512 samples.
TEST_F(RoomAccuracy, ErrorVersusProbeCount) {
  std::printf("method       start_m  param  probes | rel_rms  dark   lit | placement_s bake_s\n");
  auto run = [&](const char* name, BakeSettings b, double param) {
    b.samples = 512;
    BakeReport r;
    const data::ProbeCloud c = bake_probe_cloud(*scene_, *traced_, b, &r);
    EXPECT_TRUE(r.valid_cloud);
    std::printf("%-12s %7g %6g %7zu | %7.3f %6.3f %5.3f | %11.2f %6.2f\n", name, double(b.spacing),
                param, c.probe_count(), error(c, 0), error(c, 1), error(c, 2), r.placement_seconds,
                r.total_seconds);
    std::fflush(stdout);
    return std::pair<std::size_t, double>(c.probe_count(), error(c, 0));
  };
  std::vector<std::pair<std::size_t, double>> grid;
  for (float spacing : {2.0f, 1.5f, 1.0f, 0.75f, 0.5f}) {
    BakeSettings b;
    b.spacing = spacing;
    grid.push_back(run("grid", b, 0));
  }
  for (std::size_t i = 1; i < grid.size(); ++i) EXPECT_LT(grid[i].second, grid[i - 1].second);
  // Spawn and merge from the 2 m and 1 m grids at three spawn thresholds (merge 0.08).
  std::vector<std::pair<std::size_t, double>> adaptive;
  for (float start : {2.0f, 1.0f})
    for (float spawn : {0.9f, 0.7f, 0.5f}) {
      BakeSettings b;
      b.spacing = start;
      b.placement = PlacementMethod::kSpawnMerge;
      b.spawn_merge.spawn_contrast = spawn;
      adaptive.push_back(run("spawn-merge", b, spawn));
    }
  for (float start : {1.5f, 1.0f, 0.75f}) {
    BakeSettings b;
    b.spacing = start;
    b.placement = PlacementMethod::kGradient;
    adaptive.push_back(run("gradient", b, 0));
  }
  // The hypothesis: an adaptive cloud reaches a grid's error with at most half its probes.
  // Printed, not asserted (measured false in this room, docs/probe_bake.md).
  for (const auto& [gn, ge] : grid) {
    bool met = false;
    for (const auto& [an, ae] : adaptive) met = met || (ae <= ge && 2 * an <= gn);
    std::printf("grid %zu probes, error %.3f: adaptive with <= %zu probes and <= that error: %s\n",
                gn, ge, gn / 2, met ? "yes" : "no");
  }
}
}  // namespace
}  // namespace penumbra::probe_bake

namespace penumbra::probe_bake {
namespace {
// The valley (open terrain under a sky, walls, an arch): error versus probe count per method at
// 120 random points of the probe volume above the ground and outside the solids (0.5 m clear).
TEST(ValleyAccuracy, ErrorVersusProbeCount) {
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "valley.json", kData);
  const reference::Scene traced(s.desc);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(0.0f, 188.0f), uz(0.0f, 40.0f);
  PointSet free;
  while (free.points.size() < 120) {
    const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, ux, ux, uz);
    bool clear = !s.inside(p);
    for (float d : {0.5f, -0.5f})
      for (int k = 0; k < 3; ++k) {
        glm::vec3 q = p;
        q[k] += d;
        clear = clear && !s.inside(q);
      }
    if (clear) free.points.push_back(p);
  }
  reference_values(traced, free);
  std::printf("method       start_m  param  probes | rel_rms | placement_s bake_s\n");
  auto run = [&](const char* name, BakeSettings b, double param) {
    b.samples = 512;
    BakeReport r;
    const data::ProbeCloud c = bake_probe_cloud(s, traced, b, &r);
    EXPECT_TRUE(r.valid_cloud);
    const double e = set_error(c, free);
    std::printf("%-12s %7g %6g %7zu | %7.3f | %11.2f %6.2f\n", name, double(b.spacing), param,
                c.probe_count(), e, r.placement_seconds, r.total_seconds);
    std::fflush(stdout);
    return std::pair<std::size_t, double>(c.probe_count(), e);
  };
  std::vector<std::pair<std::size_t, double>> grid, adaptive;
  for (float spacing : {20.0f, 15.0f, 10.0f, 7.5f}) {
    BakeSettings b;
    b.spacing = spacing;
    grid.push_back(run("grid", b, 0));
  }
  for (float start : {20.0f, 15.0f})
    for (float spawn : {0.7f, 0.5f, 0.3f}) {
      BakeSettings b;
      b.spacing = start;
      b.placement = PlacementMethod::kSpawnMerge;
      b.spawn_merge.spawn_contrast = spawn;
      adaptive.push_back(run("spawn-merge", b, spawn));
    }
  for (float start : {15.0f, 10.0f}) {
    BakeSettings b;
    b.spacing = start;
    b.placement = PlacementMethod::kGradient;
    adaptive.push_back(run("gradient", b, 0));
  }
  for (const auto& [gn, ge] : grid) {
    bool met = false;
    for (const auto& [an, ae] : adaptive) met = met || (ae <= ge && 2 * an <= gn);
    std::printf("grid %zu probes, error %.3f: adaptive with <= %zu probes and <= that error: %s\n",
                gn, ge, gn / 2, met ? "yes" : "no");
  }
}
}  // namespace
}  // namespace penumbra::probe_bake
