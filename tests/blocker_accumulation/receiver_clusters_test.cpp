#include "penumbra/systems/blocker_accumulation/receiver_clusters.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "common/random_draws.h"
#include "common/stability.h"
#include "penumbra/sh/exp_log.h"
#include "test_skies.h"

namespace penumbra::blocker_accumulation {
namespace {

sh::CoeffsRgb<N> uniform_sh_sky() {
  sh::CoeffsRgb<N> sky{};
  for (auto& c : sky) c[0] = std::sqrt(4 * std::numbers::pi_v<float>);
  return sky;
}

// A sky brighter overhead and towards +x, different per channel (so the channels do not agree by
// accident).
sh::CoeffsRgb<N> tilted_sky() {
  sh::CoeffsRgb<N> sky = uniform_sh_sky();
  for (int c = 0; c < 3; ++c) {
    sky[c][sh::index(1, 0)] = 0.8f + 0.2f * c;
    sky[c][sh::index(1, 1)] = 0.5f - 0.2f * c;
    sky[c][sh::index(2, 0)] = 0.3f;
  }
  return sky;
}

// Upward receivers on z = 0, side x side over extent x extent metres.
struct Receivers {
  std::vector<glm::vec3> points, normals;
  int side = 0;
};

Receivers ground(int side, float extent) {
  Receivers r;
  r.side = side;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      r.points.emplace_back(extent * ((i + 0.5f) / side - 0.5f),
                            extent * ((j + 0.5f) / side - 0.5f), 0.0f);
      r.normals.emplace_back(0, 0, 1);
    }
  return r;
}

// Scattered spheres (radius 1-3 m, heights 2-10 m) and objects of 16 spheres, as the bench.
struct ClusterScene {
  std::vector<WorldSphere> spheres;
  std::vector<BlockerGroup> groups;
};

ClusterScene scattered(int count, float extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xy(-0.5f * extent, 0.5f * extent), z(2, 10), r(1, 3);
  ClusterScene s;
  for (int i = 0; i < count; ++i) s.spheres.push_back({{xy(rng), xy(rng), z(rng)}, r(rng)});
  return s;
}

ClusterScene objects(int count, float extent, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xy(-0.5f * extent, 0.5f * extent), z(4, 8), r(0.5f, 1.5f),
      u(-1, 1);
  ClusterScene s;
  for (int o = 0; o < count; ++o) {
    const glm::vec3 centre = penumbra::test::draw_zyx<glm::vec3>(rng, xy, xy, z);
    const auto first = static_cast<std::uint32_t>(s.spheres.size());
    for (int k = 0; k < 16; ++k) {
      glm::vec3 d;
      do d = penumbra::test::draw_zyx<glm::vec3>(rng, u);
      while (glm::dot(d, d) > 1);
      s.spheres.push_back({centre + 3.0f * d, r(rng)});
    }
    s.groups.push_back(bound_group(std::span(s.spheres).subspan(first, 16), first));
  }
  return s;
}

std::vector<glm::vec3> per_receiver(const BlockerAccumulation<N>& acc, const sh::CoeffsRgb<N>& sky,
                                    const Receivers& r) {
  std::vector<glm::vec3> e(r.points.size());
  acc.shade(sky, r.points, r.normals, {}, e);
  return e;
}

std::vector<glm::vec3> clustered(const ReceiverClusters<N>& rc, const BlockerAccumulation<N>& acc,
                                 const sh::CoeffsRgb<N>& sky,
                                 ReceiverClusterCounts* counts = nullptr) {
  std::vector<glm::vec3> e(rc.order().size());
  rc.shade(acc, sky, e, {}, counts);
  return e;
}

struct Error {
  double rel_rms = 0, max_rel = 0;  // against RMS(reference), over the three channels
};

Error compare(const std::vector<glm::vec3>& e, const std::vector<glm::vec3>& ref) {
  double d2 = 0, r2 = 0, dmax = 0;
  for (std::size_t i = 0; i < e.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = double(e[i][c]) - ref[i][c];
      d2 += d * d;
      r2 += double(ref[i][c]) * ref[i][c];
      dmax = std::max(dmax, std::abs(d));
    }
  Error err;
  err.rel_rms = std::sqrt(d2 / r2);
  err.max_rel = dmax / std::sqrt(r2 / (3.0 * e.size()));
  return err;
}

BlockerSettings all_pairs_settings() {
  BlockerSettings s;
  s.blocker.min_sin = 0;
  s.hierarchy = BlockerHierarchy::kOff;
  return s;
}

TEST(ReceiverClusters, RejectsBadInput) {
  PENUMBRA_STABILITY(
      "max_receivers 0; no receivers; normals of another count; a NaN receiver or infinite normal",
      "std::invalid_argument naming the receiver", "-");
  EXPECT_THROW(ReceiverClusters<N>(ReceiverClusterSettings{.max_receivers = 0}),
               std::invalid_argument);
  ReceiverClusters<N> rc;
  EXPECT_THROW(rc.set_receivers({}, {}), std::invalid_argument);
  std::vector<glm::vec3> p{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, n(3, glm::vec3(0, 0, 1));
  EXPECT_THROW(rc.set_receivers(p, std::span(n).first(2)), std::invalid_argument);
  p[2].y = std::numeric_limits<float>::quiet_NaN();
  try {
    rc.set_receivers(p, n);
    ADD_FAILURE() << "a NaN receiver was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("receiver 2"), std::string::npos) << e.what();
  }
  p[2].y = 0;
  n[1].x = std::numeric_limits<float>::infinity();
  try {
    rc.set_receivers(p, n);
    ADD_FAILURE() << "an infinite normal was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("receiver 1"), std::string::npos) << e.what();
  }
  n[1].x = 0;
  rc.set_receivers(p, n);
  BlockerAccumulation<N> acc;
  std::vector<glm::vec3> out(2);
  EXPECT_THROW(rc.shade(acc, uniform_sh_sky(), out), std::invalid_argument);
}

// Every receiver in exactly one cluster, none over max_receivers, each inside its cluster's
// radius and normal bounds.
TEST(ReceiverClusters, PartitionsTheReceivers) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<glm::vec3> p, n;
  for (int i = 0; i < 5000; ++i) {  // a ball's surface: normals all round
    glm::vec3 d;
    do d = penumbra::test::draw_zyx<glm::vec3>(rng, u);
    while (glm::dot(d, d) > 1 || glm::dot(d, d) < 1e-4f);
    d = glm::normalize(d);
    p.push_back(10.0f * d);
    n.push_back(d);
  }
  ReceiverClusters<N> rc(ReceiverClusterSettings{.max_receivers = 100});
  rc.set_receivers(p, n);
  std::set<std::uint32_t> seen(rc.order().begin(), rc.order().end());
  EXPECT_EQ(seen.size(), p.size());
  std::uint32_t next = 0;
  for (const auto& c : rc.clusters()) {
    EXPECT_EQ(c.first, next);
    next += c.count;
    EXPECT_LE(c.count, 100u);
    EXPECT_GE(c.count, 50u);
    for (std::uint32_t k = c.first; k < c.first + c.count; ++k) {
      const std::uint32_t i = rc.order()[k];
      EXPECT_LE(glm::length(p[i] - c.centre), c.radius * (1 + 1e-5f));
      EXPECT_GE(glm::dot(n[i], c.normal), c.cos_cone - 1e-5f);
      const float h = glm::dot(n[i], p[i] - c.centre);
      EXPECT_GE(h, c.h_min - 1e-4f);
      EXPECT_LE(h, c.h_max + 1e-4f);
    }
    EXPECT_GT(c.cos_cone, 0.5f) << "the split by normals keeps cones narrow";
  }
  EXPECT_EQ(next, p.size());
}

// With nothing shared (far_sin 0) and the hierarchy off, the clusters' near loop is the
// per-receiver loop: the same irradiance and visibility up to rounding.
TEST(ReceiverClusters, NothingSharedIsThePerReceiverPath) {
  const Receivers r = ground(60, 60);
  const ClusterScene s = scattered(60, 60, 5);
  BlockerSettings bs;
  bs.hierarchy = BlockerHierarchy::kOff;
  BlockerAccumulation<N> acc(bs);
  acc.set_blockers(s.spheres);
  ReceiverClusters<N> rc(ReceiverClusterSettings{.max_receivers = 64, .far_sin = 0});
  rc.set_receivers(r.points, r.normals);
  std::vector<glm::vec3> e(r.points.size()), ref(r.points.size());
  std::vector<sh::Coeffs<N>> v(r.points.size()), vref(r.points.size());
  ReceiverClusterCounts counts;
  rc.shade(acc, tilted_sky(), e, v, &counts);
  acc.shade(tilted_sky(), r.points, r.normals, vref, ref);
  EXPECT_EQ(counts.far_groups, 0u);
  EXPECT_EQ(counts.receivers, r.points.size());
  const Error err = compare(e, ref);
  EXPECT_LT(err.max_rel, 1e-4);
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < N * N; ++k) EXPECT_NEAR(v[i][k], vref[i][k], 1e-4f);
}

// Both shade() paths run the exponential, product and dots eight receivers at a time
// (sh/batch.h) for kProduct without lights: the same as irradiance() per receiver, for tilted
// normals under overlapping blockers (lanes with different HYB squarings) and a count that
// leaves a partial last batch; with a light the scalar path.
TEST(ReceiverClusters, BatchedShadingIsIrradiancePerReceiver) {
  Receivers r = ground(21, 30);  // 441 = 55 x 8 + 1
  std::mt19937 rng(5);
  std::normal_distribution<float> tilt(0, 0.4f);
  for (glm::vec3& n : r.normals) {
    const float ny = tilt(rng), nx = tilt(rng);  // GCC's order (random_draws.h)
    n = glm::normalize(glm::vec3(nx, ny, 1));
  }
  const ClusterScene s = scattered(80, 30, 9);
  for (const bool light : {false, true}) {
    BlockerAccumulation<N> acc;
    acc.set_blockers(s.spheres);
    if (light) acc.set_lights({{{3, 2, 12}, 1.5f, {2, 2, 2}}});
    ReceiverClusters<N> rc(ReceiverClusterSettings{.max_receivers = 37});
    rc.set_receivers(r.points, r.normals);
    std::vector<glm::vec3> e(r.points.size()), ec(r.points.size());
    std::vector<sh::Coeffs<N>> v(r.points.size()), vc(r.points.size());
    acc.shade(tilted_sky(), r.points, r.normals, v, e);
    rc.shade(acc, tilted_sky(), ec, vc);
    std::set<int> squarings;
    float worst = 0, worst_v = 0;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      sh::Coeffs<N> vref;
      const glm::vec3 ref = acc.irradiance(tilted_sky(), r.points[i], r.normals[i], &vref);
      const sh::Coeffs<N> log_v = acc.log_visibility(r.points[i], r.normals[i]);
      float norm2 = 0;
      for (int k = 1; k < N * N; ++k) norm2 += log_v[k] * log_v[k];
      squarings.insert(static_cast<int>(std::ceil(std::log2(std::sqrt(norm2) / sh::kHybOlNorm))));
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::fabs(e[i][c] - ref[c]) / std::max(std::fabs(ref[c]), 1e-3f));
      for (int k = 0; k < N * N; ++k) worst_v = std::max(worst_v, std::fabs(v[i][k] - vref[k]));
      EXPECT_TRUE(std::isfinite(ec[i].x) && std::isfinite(ec[i].y) && std::isfinite(ec[i].z));
    }
    std::printf(
        "light %d: shade() vs irradiance(): worst relative %.3g, visibility %.3g; %zu "
        "different squaring counts\n",
        light, worst, worst_v, squarings.size());
    EXPECT_LE(worst, 1e-5f);
    EXPECT_LE(worst_v, 1e-5f);
    EXPECT_GE(squarings.size(), 3u);
    const Error err = compare(ec, e);  // clusters: far sums shared, so close, not equal
    EXPECT_LT(err.rel_rms, 0.05);
  }
}

// The clustered frame against all pairs and against the per-receiver path (grid and
// hierarchy), on the bench's scenes scaled down: 14,400 receivers over 120 m, 144 scattered
// spheres / 9 objects of 16, the same densities. Bounds: measured (printed) plus margin.
struct Case {
  const char* name;
  ClusterScene scene;
  double max_rms_vs_all, max_max_vs_all, max_rms_vs_receiver, max_max_vs_receiver;
};

TEST(ReceiverClusters, MatchesThePerReceiverPathAndAllPairs) {
  const Receivers r = ground(120, 120);
  const sh::CoeffsRgb<N> sky = tilted_sky();
  ReceiverClusters<N> rc;
  rc.set_receivers(r.points, r.normals);
  const Case cases[] = {
      {"scattered:144", scattered(144, 120, 11), 0.03, 0.09, 0.005, 0.03},
      {"objects:9x16", objects(9, 120, 12), 0.015, 0.10, 0.025, 0.10},
  };
  for (const Case& c : cases) {
    BlockerAccumulation<N> acc, all(all_pairs_settings());
    acc.set_blockers(c.scene.spheres, c.scene.groups);
    all.set_blockers(c.scene.spheres, c.scene.groups);
    ReceiverClusterCounts counts;
    const std::vector<glm::vec3> e = clustered(rc, acc, sky, &counts);
    const std::vector<glm::vec3> ref = per_receiver(acc, sky, r), exact = per_receiver(all, sky, r);
    const Error vs_all = compare(e, exact), vs_receiver = compare(e, ref),
                receiver_vs_all = compare(ref, exact);
    std::printf(
        "%s: clusters vs all pairs rel RMS %.3f%% max %.3f%%; vs per receiver %.3f%% / %.3f%%; "
        "per receiver vs all pairs %.3f%% / %.3f%%; far %zu near %zu (plane %zu) groups, shared "
        "receivers %zu of %zu\n",
        c.name, 100 * vs_all.rel_rms, 100 * vs_all.max_rel, 100 * vs_receiver.rel_rms,
        100 * vs_receiver.max_rel, 100 * receiver_vs_all.rel_rms, 100 * receiver_vs_all.max_rel,
        counts.far_groups, counts.near_groups, counts.near_by_plane, counts.shared_receivers,
        counts.receivers);
    EXPECT_GT(2 * counts.far_groups, counts.near_groups) << c.name << ": many groups shared";
    EXPECT_LT(vs_all.rel_rms, c.max_rms_vs_all) << c.name;
    EXPECT_LT(vs_all.max_rel, c.max_max_vs_all) << c.name;
    EXPECT_LT(vs_receiver.rel_rms, c.max_rms_vs_receiver) << c.name;
    EXPECT_LT(vs_receiver.max_rel, c.max_max_vs_receiver) << c.name;
  }
}

// Seams: on the receiver grid, the largest step between 4-neighbours in different clusters,
// beyond the step the per-receiver path has there, against the same for neighbours in one
// cluster (relative to the mean irradiance).
struct Seams {
  double across = 0, inside = 0;          // largest |dE| - |dE_ref|, relative
  double raw_across = 0, raw_inside = 0;  // largest |dE|, relative
};

Seams seams(const ReceiverClusters<N>& rc, const Receivers& r, const std::vector<glm::vec3>& e,
            const std::vector<glm::vec3>& ref) {
  std::vector<std::uint32_t> cluster_of(r.points.size());
  for (std::uint32_t c = 0; c < rc.clusters().size(); ++c)
    for (std::uint32_t k = 0; k < rc.clusters()[c].count; ++k)
      cluster_of[rc.order()[rc.clusters()[c].first + k]] = c;
  double mean = 0;
  for (const glm::vec3& x : ref) mean += x.y;
  mean /= static_cast<double>(ref.size());
  Seams s;
  const auto pair = [&](std::size_t a, std::size_t b) {
    const double step = std::abs(double(e[a].y) - e[b].y) / mean;
    const double excess = step - std::abs(double(ref[a].y) - ref[b].y) / mean;
    const bool across = cluster_of[a] != cluster_of[b];
    double& x = across ? s.across : s.inside;
    double& raw = across ? s.raw_across : s.raw_inside;
    x = std::max(x, excess);
    raw = std::max(raw, step);
  };
  for (int j = 0; j < r.side; ++j)
    for (int i = 0; i < r.side; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * r.side + i;
      if (i + 1 < r.side) pair(k, k + 1);
      if (j + 1 < r.side) pair(k, k + r.side);
    }
  return s;
}

// The clusters take the blockers' log as the settings say: with [Ren06]'s clipped eigenvalue
// log (SphereBlockerSettings::log) they follow the per-receiver path as closely as with the eps
// cap, and differ from the eps cap's clusters.
TEST(ReceiverClusters, FollowTheClippedEigenLog) {
  const Receivers r = ground(60, 60);
  const sh::CoeffsRgb<N> sky = tilted_sky();
  ReceiverClusters<N> rc;
  rc.set_receivers(r.points, r.normals);
  const ClusterScene scene = scattered(60, 60, 11);
  BlockerSettings ren;
  ren.blocker.log = BlockerLog::kClippedEigen;
  BlockerAccumulation<N> acc(ren), cap;
  acc.set_blockers(scene.spheres, scene.groups);
  cap.set_blockers(scene.spheres, scene.groups);
  const std::vector<glm::vec3> e = clustered(rc, acc, sky, nullptr);
  const Error vs_receiver = compare(e, per_receiver(acc, sky, r));
  const Error vs_cap = compare(e, clustered(rc, cap, sky, nullptr));
  std::printf(
      "clipped log: clusters vs per receiver rel RMS %.3f%% max %.3f%%; vs the eps cap's "
      "clusters %.3f%%\n",
      100 * vs_receiver.rel_rms, 100 * vs_receiver.max_rel, 100 * vs_cap.rel_rms);
  EXPECT_LT(vs_receiver.rel_rms, 0.005);
  EXPECT_LT(vs_receiver.max_rel, 0.03);
  EXPECT_GT(vs_cap.rel_rms, 0.001);  // a different log, not the eps cap again
}

TEST(ReceiverClusters, NoSeamsBetweenClusters) {
  const Receivers r = ground(120, 120);  // 1 m apart
  const sh::CoeffsRgb<N> sky = uniform_sh_sky();
  struct SeamCase {
    const char* name;
    ClusterScene scene;
    bool band_ratio;
    double bound;  // largest step across clusters beyond the per-receiver path's, relative
  };
  const SeamCase cases[] = {
      {"scattered:144", scattered(144, 120, 11), true, 0.02},
      {"objects:9x16, band ratio", objects(9, 120, 12), true, 0.07},
      {"objects:9x16, coverage", objects(9, 120, 12), false, 0.03},
  };
  for (const SeamCase& c : cases) {
    ReceiverClusters<N> rc(ReceiverClusterSettings{.band_ratio = c.band_ratio});
    rc.set_receivers(r.points, r.normals);
    BlockerAccumulation<N> acc;
    acc.set_blockers(c.scene.spheres, c.scene.groups);
    const std::vector<glm::vec3> e = clustered(rc, acc, sky), ref = per_receiver(acc, sky, r);
    const Seams s = seams(rc, r, e, ref);
    std::printf(
        "seams, %s: largest step across clusters %.3f%% (inside %.3f%%); beyond the "
        "per-receiver path's step: across %.3f%%, inside %.3f%%\n",
        c.name, 100 * s.raw_across, 100 * s.raw_inside, 100 * s.across, 100 * s.inside);
    EXPECT_LT(s.across, c.bound) << c.name;
  }
}

// Curved receivers (a ball's surface under scattered spheres): the plane rule keeps blockers
// near the receivers' horizons per receiver, and the result still matches.
TEST(ReceiverClusters, CurvedReceiversKeepThePlaneRule) {
  std::vector<glm::vec3> p, n;
  const int rings = 60, per_ring = 120;
  for (int a = 0; a < rings; ++a)
    for (int b = 0; b < per_ring; ++b) {
      const float th = std::numbers::pi_v<float> * (a + 0.5f) / rings;
      const float ph = 2 * std::numbers::pi_v<float> * b / per_ring;
      const glm::vec3 d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      p.push_back(glm::vec3(0, 0, 20) + 8.0f * d);
      n.push_back(d);
    }
  ClusterScene s = scattered(200, 120, 21);
  for (auto& x : s.spheres) x.centre.z *= 4;  // some above the ball too
  const sh::CoeffsRgb<N> sky = tilted_sky();
  BlockerAccumulation<N> acc;
  acc.set_blockers(s.spheres);
  ReceiverClusters<N> rc(ReceiverClusterSettings{.max_receivers = 64});
  rc.set_receivers(p, n);
  std::vector<glm::vec3> e(p.size()), ref(p.size());
  ReceiverClusterCounts counts;
  rc.shade(acc, sky, e, {}, &counts);
  acc.shade(sky, p, n, {}, ref);
  const Error err = compare(e, ref);
  std::printf("ball: vs per receiver rel RMS %.3f%% max %.3f%%; far %zu near %zu (plane %zu)\n",
              100 * err.rel_rms, 100 * err.max_rel, counts.far_groups, counts.near_groups,
              counts.near_by_plane);
  EXPECT_GT(counts.near_by_plane, 0u);
  EXPECT_GT(counts.far_groups, 0u);
  EXPECT_LT(err.rel_rms, 0.02);
  EXPECT_LT(err.max_rel, 0.1);
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
