#include "penumbra/systems/probe_cloud/probe_systems.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "common/frame_work.h"
#include "common/random_draws.h"
#include "common/stability.h"
#include "penumbra/components/frame_time.h"
#include "penumbra/components/probe_anchor.h"
#include "penumbra/components/probe_cloud_resource.h"
#include "penumbra/components/probe_lighting.h"
#include "penumbra/components/transform.h"
#include "penumbra/jobs/executor.h"
#include "probe_walk_test_util.h"

namespace penumbra::probe_cloud {
namespace {

using components::FrameTime;
using components::ProbeAnchor;
using components::ProbeCloudResource;
using components::ProbeLighting;
using components::Transform;
using test::make_cloud;
using test::max_abs_diff;

Transform at(const glm::vec3& p) {
  return Transform{glm::translate(glm::mat4(1.0f), p)};
}

struct Scene {
  ecs::World world;
  jobs::Schedule schedule;
  jobs::Executor executor;
  std::vector<ecs::Entity> entities;
  glm::vec3 offset{0.0f};  // every entity's anchor offset
  explicit Scene(std::shared_ptr<const data::ProbeCloud> cloud, int threads = 2)
      : executor(threads) {
    emplace_probe_cloud_resources(world, std::move(cloud));
    add_probe_cloud_systems(schedule);
  }
  // Entities whose sample points (Transform * offset) are `positions`.
  void spawn(const std::vector<glm::vec3>& positions,
             const glm::vec3& anchor_offset = glm::vec3(0)) {
    offset = anchor_offset;
    for (const glm::vec3& p : positions) {
      ProbeAnchor a;
      a.offset = offset;
      entities.push_back(world.create_with(at(p - offset), a, ProbeLighting{}));
    }
  }
  void move(const std::vector<glm::vec3>& positions) {
    for (std::size_t i = 0; i < positions.size(); ++i)
      *world.get_mut<Transform>(entities[i]) = at(positions[i] - offset);
  }
  void run() { executor.run(schedule, world); }
  const ProbeWalkReport& report() { return world.resource<const ProbeWalkReport>(); }
  const ProbeTetWalk& walk() { return *world.resource<const ProbeWalkState>().walk; }
};

// Every entity's lighting equals a direct locate + interpolate at its sample point.
void expect_matches_direct(Scene& s, const std::vector<glm::vec3>& positions) {
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const ProbeLighting* l = s.world.get<ProbeLighting>(s.entities[i]);
    ASSERT_NE(l, nullptr);
    ASSERT_TRUE(l->valid);
    const ProbeWalkResult r = s.walk().locate(positions[i], -1);
    sh::CoeffsRgb<ProbeLighting::kBands> direct;
    s.walk().interpolate(r, direct);
    ASSERT_LT(max_abs_diff(l->irradiance, direct), 2e-4f) << "entity " << i;
    EXPECT_GE(s.world.get<ProbeAnchor>(s.entities[i])->cell, 0);
  }
}

TEST(ProbeSystems, MovingEntitiesGetTheInterpolatedShAndKeepTheirCells) {
  const auto points = test::random_points(300, 10.0f, 31);
  Scene s(make_cloud(points, test::random_sh(points.size(), 3, 32)));
  auto positions = test::random_points(2000, 12.0f, 33);  // some outside the hull
  s.spawn(positions, glm::vec3(0.1f, 0.0f, 0.2f));
  s.run();
  ASSERT_TRUE(s.report().errors.empty());
  EXPECT_EQ(s.report().entities, positions.size());
  EXPECT_EQ(s.report().fallbacks, positions.size());  // no cache yet
  expect_matches_direct(s, positions);
  s.run();  // nothing moved: every entity skipped, same lighting
  EXPECT_EQ(s.report().entities, 0u);
  EXPECT_EQ(s.report().unchanged, positions.size());
  expect_matches_direct(s, positions);
  std::mt19937 rng(34);
  std::uniform_real_distribution<float> step(-0.1f, 0.1f);
  for (int frame = 0; frame < 3; ++frame) {
    for (glm::vec3& p : positions) p += penumbra::test::draw_zyx<glm::vec3>(rng, step);
    s.move(positions);
    s.run();
    EXPECT_EQ(s.report().entities, positions.size());
    // Small moves walk from the cache; a few entities outside the hull, far from every vertex of
    // a large outer cell, take the grid (the far check).
    EXPECT_LT(s.report().fallbacks, positions.size() / 100);
    expect_matches_direct(s, positions);
  }
}

// The frame table's work report (jobs::report_work): entities walked, and entities skipped
// because they did not move.
TEST(ProbeSystems, ReportsTheWorkItSkipsPerFrame) {
  const auto points = test::random_points(100, 10.0f, 41);
  Scene s(make_cloud(points, test::random_sh(points.size(), 3, 42)));
  auto positions = test::random_points(500, 9.0f, 43);
  s.spawn(positions);
  s.run();
  auto walk = [&] { return penumbra::test::system_timing(s.executor.last_frame(), "probes.walk"); };
  EXPECT_TRUE(walk().reported);
  EXPECT_EQ(walk().done, 500u);
  EXPECT_EQ(walk().skipped, 0u);
  s.run();
  EXPECT_EQ(walk().done, 0u) << "nothing moved";
  EXPECT_EQ(walk().skipped, 500u);
  for (std::size_t i = 0; i < 100; ++i) positions[i].x += 0.05f;
  s.move(positions);
  s.run();
  EXPECT_EQ(walk().done, 100u);
  EXPECT_EQ(walk().skipped, 400u);
}

TEST(ProbeSystems, ReplacingTheCloudInvalidatesEveryCachedCell) {
  PENUMBRA_STABILITY("the cloud replaced by one with the same cell count",
                     "every cached cell invalidated (generation): full locate, no stale cell", "-");
  const auto points = test::random_points(300, 10.0f, 35);
  Scene s(make_cloud(points, test::random_sh(points.size(), 3, 36)));
  const auto positions = test::random_points(500, 10.0f, 37);
  s.spawn(positions);
  s.run();
  s.run();
  EXPECT_EQ(s.report().fallbacks, 0u);
  const std::uint64_t g = s.world.resource<const ProbeWalkState>().generation;
  // Another scene: the same number of cells would make old indices look valid.
  const auto other = test::random_points(300, 10.0f, 38);
  s.world.resource<ProbeCloudResource>().replace(
      make_cloud(other, test::random_sh(other.size(), 3, 39)));
  s.run();
  EXPECT_GT(s.world.resource<const ProbeWalkState>().generation, g);
  EXPECT_EQ(s.report().fallbacks, positions.size());
  expect_matches_direct(s, positions);
  for (ecs::Entity e : s.entities)
    EXPECT_EQ(s.world.get<ProbeAnchor>(e)->generation,
              s.world.resource<const ProbeWalkState>().generation);
  // Assigning the pointer without replace() is caught too.
  s.world.resource<ProbeCloudResource>().cloud = make_cloud(points, test::random_sh(300, 3, 40));
  s.run();
  EXPECT_EQ(s.report().fallbacks, positions.size());
  expect_matches_direct(s, positions);
}

TEST(ProbeSystems, NonFiniteEntitiesAreSkippedAndNamed) {
  PENUMBRA_STABILITY("entities with non-finite sample points",
                     "skipped and named (20, then a count); their lighting and cell kept", "-");
  const auto points = test::random_points(100, 10.0f, 41);
  Scene s(make_cloud(points, test::random_sh(points.size(), 3, 42)));
  s.spawn({{5, 5, 5}, {4, 4, 4}, {6, 5, 4}});
  s.run();
  const ProbeLighting before = *s.world.get<ProbeLighting>(s.entities[1]);
  const ProbeAnchor anchor_before = *s.world.get<ProbeAnchor>(s.entities[1]);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  s.world.get_mut<Transform>(s.entities[1])->world[3].y = nan;
  s.world.get_mut<ProbeAnchor>(s.entities[2])->offset.x = std::numeric_limits<float>::infinity();
  s.run();
  ASSERT_EQ(s.report().errors.size(), 2u);
  EXPECT_EQ(s.report().rejected, 2u);
  EXPECT_EQ(s.report().entities + s.report().unchanged, 1u);
  const std::string name1 = "entity " + std::to_string(s.entities[1].index) + "v" +
                            std::to_string(s.entities[1].generation);
  EXPECT_NE(s.report().errors[0].find(name1), std::string::npos) << s.report().errors[0];
  EXPECT_NE(s.report().errors[0].find("not finite"), std::string::npos);
  const ProbeLighting& after = *s.world.get<ProbeLighting>(s.entities[1]);
  EXPECT_EQ(max_abs_diff(after.irradiance, before.irradiance), 0.0f);
  EXPECT_EQ(s.world.get<ProbeAnchor>(s.entities[1])->cell, anchor_before.cell);
  // Many at once: 20 named, then a count.
  s.spawn(std::vector<glm::vec3>(100, glm::vec3(std::numeric_limits<float>::infinity())));
  s.run();
  EXPECT_EQ(s.report().rejected, 102u);
  ASSERT_EQ(s.report().errors.size(), 21u);
  EXPECT_EQ(s.report().errors.back(), "... and 82 more entities with a non-finite sample point");
}

TEST(ProbeSystems, SmoothingStartsFromTheFirstSample) {
  const auto points = test::grid_points(4, 4, 4, 2.0f);
  // Probe brightness grows with x: moving along x changes the sample.
  std::vector<float> sh(points.size() * 27, 0.0f);
  for (std::size_t k = 0; k < points.size(); ++k)
    for (std::size_t ch = 0; ch < 3; ++ch) sh[(k * 3 + ch) * 9] = 1.0f + points[k].x;
  Scene s(make_cloud(points, sh));
  auto& settings = s.world.resource<ProbeSettingsResource>();
  settings.smoothing = ProbeSmoothing::kExponential;
  settings.time_constant = 0.5f;
  s.world.emplace_resource<FrameTime>().dt = 0.1f;
  s.spawn({{1, 3, 3}});
  s.run();
  const ProbeLighting& l = *s.world.get<ProbeLighting>(s.entities[0]);
  EXPECT_NEAR(l.irradiance[0][0], 2.0f, 1e-5f);  // the first sample, not black
  const auto sample_at = [&](const glm::vec3& p) {
    sh::CoeffsRgb<ProbeLighting::kBands> out;
    s.walk().interpolate(s.walk().locate(p, -1), out);
    return out;
  };
  EXPECT_EQ(max_abs_diff(l.irradiance, sample_at({1, 3, 3})), 0.0f);
  s.move({{5, 3, 3}});
  s.run();
  const ProbeLighting& m = *s.world.get<ProbeLighting>(s.entities[0]);
  EXPECT_NEAR(sample_at({5, 3, 3})[0][0], 6.0f, 1e-5f);
  const float alpha = smoothing_alpha(0.1f, 0.5f);
  EXPECT_NEAR(alpha, 1.0f - std::exp(-0.2f), 1e-6f);
  EXPECT_NEAR(m.irradiance[0][0], 2.0f + 4.0f * alpha, 1e-5f);
  // Not moving: the walk is skipped, the smoothing goes on towards the same sample (rebuilt
  // from the cached cell: the unsmoothed sample is not stored).
  s.run();
  EXPECT_EQ(s.report().unchanged, 1u);
  EXPECT_EQ(s.report().entities, 0u);
  EXPECT_NEAR(s.world.get<ProbeLighting>(s.entities[0])->irradiance[0][0],
              2.0f + 4.0f * (1.0f - (1.0f - alpha) * (1.0f - alpha)), 1e-5f);
  for (int i = 0; i < 60; ++i) s.run();
  EXPECT_NEAR(s.world.get<ProbeLighting>(s.entities[0])->irradiance[0][0], 6.0f, 1e-3f);
  EXPECT_LT(
      max_abs_diff(s.world.get<ProbeLighting>(s.entities[0])->irradiance, sample_at({5, 3, 3})),
      1e-3f);
  EXPECT_EQ(smoothing_alpha(0.1f, 0.0f), 1.0f);
}

TEST(ProbeSystems, NoCloudWritesNothingAndAnEmptyCloudGivesZero) {
  PENUMBRA_STABILITY("no cloud; an empty cloud", "nothing written; zero lighting", "-");
  Scene s(nullptr);
  s.spawn({{1, 2, 3}});
  s.run();
  EXPECT_FALSE(s.world.get<ProbeLighting>(s.entities[0])->valid);
  EXPECT_EQ(s.report().entities, 0u);
  s.world.resource<ProbeCloudResource>().replace(make_cloud({}, {}));
  s.run();
  const ProbeLighting& l = *s.world.get<ProbeLighting>(s.entities[0]);
  EXPECT_TRUE(l.valid);
  EXPECT_EQ(l.irradiance[0][0], 0.0f);
  EXPECT_EQ(s.world.get<ProbeAnchor>(s.entities[0])->cell, kNoCell);
}

TEST(ProbeSystems, AnInconsistentCloudIsRejectedWithItsReason) {
  PENUMBRA_STABILITY(
      "an inconsistent cloud (SH of the wrong size)",
      "rejected with its reason, lighting invalid; a good cloud afterwards is taken up", "-");
  const auto points = test::random_points(50, 10.0f, 52);
  auto bad = std::make_shared<data::ProbeCloud>(*make_cloud(points, {}));
  bad->sh.resize(7);
  Scene s(bad);
  s.spawn({{5, 5, 5}});
  s.run();
  const ProbeWalkState& state = s.world.resource<const ProbeWalkState>();
  EXPECT_EQ(state.walk, nullptr);
  EXPECT_NE(state.error.find("sh has 7 floats"), std::string::npos) << state.error;
  EXPECT_FALSE(s.world.get<ProbeLighting>(s.entities[0])->valid);
  // A good cloud afterwards is taken up.
  s.world.resource<ProbeCloudResource>().replace(make_cloud(points, {}));
  s.run();
  EXPECT_TRUE(s.world.resource<const ProbeWalkState>().error.empty());
  EXPECT_TRUE(s.world.get<ProbeLighting>(s.entities[0])->valid);
}

TEST(ProbeSystems, ResultsDoNotDependOnTheThreadCount) {
  const auto points = test::random_points(500, 10.0f, 43);
  const auto cloud = make_cloud(points, test::random_sh(points.size(), 3, 44));
  const auto positions = test::random_points(20000, 11.0f, 45);
  Scene one(cloud, 1), two(cloud, 2);
  one.spawn(positions);
  two.spawn(positions);
  one.run();
  two.run();
  EXPECT_EQ(one.report().steps, two.report().steps);
  EXPECT_EQ(one.report().fallbacks, two.report().fallbacks);
  for (std::size_t i = 0; i < positions.size(); i += 7)
    ASSERT_EQ(max_abs_diff(one.world.get<ProbeLighting>(one.entities[i])->irradiance,
                           two.world.get<ProbeLighting>(two.entities[i])->irradiance),
              0.0f);
}

}  // namespace
}  // namespace penumbra::probe_cloud
