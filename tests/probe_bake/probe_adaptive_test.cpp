// Adaptive placement (probe_adaptive.h, probe_sampling.h; [Sukys14] sec. 3.1.1-3.1.3) with
// synthetic light fields through the capture callback, and the bake's --method end to end.
#include "penumbra/systems/probe_bake/probe_adaptive.h"

#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/stability.h"
#include "penumbra/assets/probe_cloud_file.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/probe_bake/probe_bake.h"
#include "penumbra/systems/probe_bake/probe_sampling.h"
#include "test_paths.h"

namespace penumbra::probe_bake {
namespace {

BakeScene open_box() {
  return parse_bake_scene(R"({"probes": {"min": [0,0,0], "max": [4,4,4], "spacing": 1}})",
                          "box.json", kData);
}

// A capture whose irradiance is isotropic with value f(p) (DC only, 3 bands); never a back face.
CaptureFn field(std::function<float(const glm::vec3&)> f, std::size_t* calls = nullptr) {
  return [f, calls](std::span<const glm::vec3> pts, bool, std::vector<float>& sh,
                    std::vector<float>& share) {
    sh.assign(pts.size() * 27, 0.0f);
    share.assign(pts.size(), 0.0f);
    for (std::size_t i = 0; i < pts.size(); ++i)
      for (int c = 0; c < 3; ++c) sh[i * 27 + c * 9] = f(pts[i]) / 0.2820948f;
    if (calls) *calls += pts.size();
  };
}

TEST(ProbeSampling, TwentySixDirections) {
  const auto& d = sample_directions();
  glm::vec3 sum(0.0f);
  for (int i = 0; i < kSampleDirections; ++i) {
    EXPECT_NEAR(glm::length(d[i]), 1.0f, 1e-6f);
    sum += d[i];
    for (int j = 0; j < i; ++j) EXPECT_LT(glm::dot(d[i], d[j]), 0.99f) << i << " " << j;
  }
  EXPECT_LT(glm::length(sum), 1e-5f);  // symmetric set
  EXPECT_EQ(d[0], glm::vec3(1, 0, 0));
  EXPECT_NEAR(d[6].x, std::sqrt(0.5f), 1e-6f);           // first edge: (1, 1, 0) / sqrt 2
  EXPECT_NEAR(d[25].z, -1.0f / std::sqrt(3.0f), 1e-6f);  // last corner: (-1, -1, -1) / sqrt 3
}

TEST(ProbeSampling, ContrastAndVector) {
  DirectionSamples a{}, b{};
  a.fill(1.0f);
  b.fill(1.0f);
  EXPECT_EQ(probe_contrast(a, b, 0.0f), 0.0f);
  b[3] = 3.0f;
  EXPECT_FLOAT_EQ(probe_contrast(a, b, 0.0f), 0.5f);  // |1 - 3| / (1 + 3)
  DirectionSamples black{};
  EXPECT_EQ(probe_contrast(black, black, 0.0f), 0.0f);
  EXPECT_EQ(irradiance_vector(black), glm::vec3(0.0f));
  EXPECT_LT(glm::length(irradiance_vector(a)), 1e-6f);  // isotropic: no direction
  // Light from +x: E(n) = max(0, n.x) -> the vector points to +x.
  std::vector<float> sh(27, 0.0f);
  const auto y = sh::eval_basis<3>(glm::vec3(1, 0, 0));
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 4; ++i) sh[c * 9 + i] = y[i];  // a +x lobe
  const glm::vec3 v = irradiance_vector(sample_irradiance(sh, 3));
  EXPECT_GT(v.x, 0.2f);
  EXPECT_NEAR(v.y, 0.0f, 1e-5f);
  EXPECT_NEAR(v.z, 0.0f, 1e-5f);
}

TEST(ProbeSpawnMerge, UniformLightMergesAndStops) {
  const BakeScene s = open_box();
  AdaptiveReport r;
  const auto pts =
      spawn_merge_points(s, s.volume, 3, 0.25f, {}, field([](auto&) { return 1.0f; }), &r);
  EXPECT_EQ(r.initial, 125u);
  EXPECT_EQ(r.spawned, 0u);
  EXPECT_GT(r.merged, 0u);
  EXPECT_LT(pts.size(), 125u);
  EXPECT_EQ(pts.size(), r.counts.back());
}

TEST(ProbeSpawnMerge, StepSpawnsAtTheStep) {
  const BakeScene s = open_box();
  SpawnMergeSettings set;
  set.merge_contrast = 0;  // spawns only
  AdaptiveReport r;
  const auto pts =
      spawn_merge_points(s, s.volume, 3, 0.25f, set,
                         field([](const glm::vec3& p) { return p.x < 1.5f ? 1.f : 10.f; }), &r);
  EXPECT_GT(r.spawned, 0u);
  EXPECT_EQ(r.merged, 0u);
  std::size_t grid = 0;
  for (const glm::vec3& p : pts) {
    const bool on_grid = p == glm::round(p);
    grid += on_grid;
    if (!on_grid) {  // every spawned probe is between the columns x = 1 and x = 2
      EXPECT_GE(p.x, 1.0f);
      EXPECT_LE(p.x, 2.0f);
    }
  }
  EXPECT_EQ(grid, 125u);
}

TEST(ProbeSpawnMerge, StopsAtItsCapAndIsDeterministic) {
  PENUMBRA_STABILITY("spawn-merge with a probe cap below what the light asks for",
                     "stops at the cap, the same probes every run", "--max-probes");
  const BakeScene s = open_box();
  SpawnMergeSettings set;
  set.max_probes = 140;
  set.merge_contrast = 0;
  auto f = field([](const glm::vec3& p) { return 1.0f + p.x * p.x * p.y; });
  AdaptiveReport r;
  const auto a = spawn_merge_points(s, s.volume, 3, 0.25f, set, f, &r);
  EXPECT_EQ(r.stop, AdaptiveReport::Stop::kProbeCap);
  EXPECT_LE(a.size(), 140u);
  EXPECT_EQ(spawn_merge_points(s, s.volume, 3, 0.25f, set, f), a);
  set.max_iterations = 1;
  set.max_probes = 100000;
  AdaptiveReport one;
  spawn_merge_points(s, s.volume, 3, 0.25f, set, f, &one);
  EXPECT_EQ(one.iterations, 1);
  EXPECT_EQ(one.stop, AdaptiveReport::Stop::kIterations);
}

TEST(ProbeGradient, ClimbsAndRevertsInTheDarkAndClustersBlackProbes) {
  const BakeScene s = open_box();
  // Light only for x < 3.2 (directional towards -x, brighter at lower x); x >= 3.2 black.
  CaptureFn f = [](std::span<const glm::vec3> pts, bool, std::vector<float>& sh,
                   std::vector<float>& share) {
    sh.assign(pts.size() * 27, 0.0f);
    share.assign(pts.size(), 0.0f);
    const auto y = sh::eval_basis<3>(glm::vec3(-1, 0, 0));
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (pts[i].x >= 3.2f) continue;
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 4; ++k) sh[i * 27 + c * 9 + k] = (4 - pts[i].x) * y[k];
    }
  };
  GradientSettings set;
  AdaptiveReport r;
  const auto pts = gradient_points(s, s.volume, 3, 0.25f, set, f, &r);
  EXPECT_GT(r.moves, 0u);
  EXPECT_EQ(r.black, 25u);    // the column x = 4
  EXPECT_EQ(r.clusters, 4u);  // ceil(25 / 8)
  EXPECT_LE(r.iterations, set.max_iterations);
  // Lit probes climbed towards -x and stayed in the volume; none ended in the black region.
  std::size_t lit = 0;
  for (const glm::vec3& p : pts)
    if (p.x < 3.2f) {
      ++lit;
      EXPECT_GE(p.x, 0.0f);
    }
  EXPECT_GT(lit, 0u);
  EXPECT_EQ(gradient_points(s, s.volume, 3, 0.25f, set, f), pts);
}

TEST(ProbeGradient, StepIntoTheDarkIsReverted) {
  PENUMBRA_STABILITY("a gradient step that takes a lit probe into the dark",
                     "the step is reverted; black probes clustered (50 -> 7)", "-");
  const BakeScene s = open_box();
  // Light towards +x everywhere below x = 2.5, black above: probes at x = 2 step into the dark.
  CaptureFn f = [](std::span<const glm::vec3> pts, bool, std::vector<float>& sh,
                   std::vector<float>& share) {
    sh.assign(pts.size() * 27, 0.0f);
    share.assign(pts.size(), 0.0f);
    const auto y = sh::eval_basis<3>(glm::vec3(1, 0, 0));
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (pts[i].x < 2.5f)
        for (int c = 0; c < 3; ++c)
          for (int k = 0; k < 4; ++k) sh[i * 27 + c * 9 + k] = y[k];
  };
  GradientSettings set;
  set.step = 2.0f;
  AdaptiveReport r;
  const auto pts = gradient_points(s, s.volume, 3, 0.25f, set, f, &r);
  EXPECT_GT(r.reverted, 0u);
  // The black columns x = 3, 4 are clustered (ceil(50 / 8) = 7 probes); no lit probe moved into
  // the dark (x in [2.5, 3)) or past it.
  EXPECT_EQ(r.black, 50u);
  std::size_t dark = 0;
  for (const glm::vec3& p : pts) {
    EXPECT_FALSE(p.x >= 2.5f && p.x < 3.0f) << p.x;
    dark += p.x >= 2.5f;
  }
  EXPECT_EQ(dark, 7u);
}

TEST(ProbeBakeMethods, RoomSpawnMergeAndGradient) {
  const BakeScene s = load_bake_scene(kRoot / "scenes" / "room.json", kData);
  const reference::Scene traced(s.desc);
  for (PlacementMethod m : {PlacementMethod::kSpawnMerge, PlacementMethod::kGradient}) {
    BakeSettings b;
    b.samples = 32;
    b.spacing = 2;
    b.placement = m;
    b.spawn_merge.max_probes = 150;
    BakeReport r;
    const data::ProbeCloud c = bake_probe_cloud(s, traced, b, &r);
    EXPECT_TRUE(r.valid_cloud);
    EXPECT_GT(r.adaptive.captured, 0u);
    if (m == PlacementMethod::kSpawnMerge) {
      EXPECT_LE(r.placed, 150u);
    }
    EXPECT_EQ(assets::encode_probe_cloud_file(bake_probe_cloud(s, traced, b)),
              assets::encode_probe_cloud_file(c));
  }
}

}  // namespace
}  // namespace penumbra::probe_bake
