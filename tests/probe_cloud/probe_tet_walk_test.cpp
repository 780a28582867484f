#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "common/random_draws.h"
#include "common/stability.h"
#include "probe_walk_test_util.h"

namespace penumbra::probe_cloud {
namespace {

using test::brute_force_cell;
using test::interpolate_cell;
using test::make_cloud;
using test::max_abs_diff;
using test::min_weight;

constexpr float kContainTol = 1e-4f;  // a weight this negative still counts as inside (float)

void expect_convex(const ProbeWalkResult& r, const std::string& where) {
  float sum = 0;
  for (float w : r.weights) {
    ASSERT_TRUE(std::isfinite(w)) << where;
    ASSERT_GE(w, 0.0f) << where;
    sum += w;
  }
  ASSERT_NEAR(sum, 1.0f, 1e-5f) << where;
}

// The walk's cell holds p (as the brute-force search's does) and both interpolate the same SH.
void check_against_brute_force(const ProbeTetWalk& walk, const glm::vec3& p, std::int32_t start,
                               ProbeWalkResult* out = nullptr) {
  const data::ProbeCloud& cloud = walk.cloud();
  const ProbeWalkResult r = walk.locate(p, start);
  const std::string where = "p = (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
                            std::to_string(p.z) + "), start " + std::to_string(start);
  ASSERT_GE(r.cell, 0) << where;
  expect_convex(r, where);
  const float walk_min = min_weight(cell_weights(cloud, static_cast<std::uint32_t>(r.cell), p));
  float brute_min = 0;
  const std::int32_t brute = brute_force_cell(cloud, p, &brute_min);
  ASSERT_GE(brute_min, -kContainTol) << where << ": brute force found no cell (cloud broken?)";
  ASSERT_GE(walk_min, -kContainTol)
      << where << ": walk ended in cell " << r.cell << " (brute force: " << brute << ")";
  const ProbeSh a = walk.interpolate(r), b = interpolate_cell(cloud, brute, p);
  ASSERT_LT(max_abs_diff(a, b), 2e-4f) << where << " cells " << r.cell << " / " << brute;
  if (out) *out = r;
}

void random_queries(const ProbeTetWalk& walk, float lo, float hi, int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi), jitter(-0.3f, 0.3f);
  std::int32_t cached = -1;
  glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, u);
  for (int i = 0; i < count; ++i) {
    // Half teleports (a new random point), half small moves from the cached cell.
    if (i % 2 == 0)
      p = {u(rng), u(rng), u(rng)};
    else
      p += penumbra::test::draw_zyx<glm::vec3>(rng, jitter);
    ProbeWalkResult r;
    ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, p, cached, &r));
    cached = r.cell;
  }
}

TEST(ProbeTetWalk, RandomCloudMatchesBruteForceInsideAndOutsideTheHull) {
  const auto points = test::random_points(300, 10.0f, 1);
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 3, 2)));
  ASSERT_GT(walk.cloud().inner_count, 0u);
  random_queries(walk, -5.0f, 15.0f, 2000, 3);  // about half outside the hull
  random_queries(walk, 1.0f, 9.0f, 1000, 4);    // mostly inside
}

TEST(ProbeTetWalk, GridCloudMatchesBruteForce) {
  const auto points = test::grid_points(10, 10, 10, 1.0f);
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 3, 5)));
  ASSERT_GT(walk.cloud().inner_count, 0u);
  random_queries(walk, -3.0f, 12.0f, 1500, 6);
}

// On vertices, edge midpoints and face centroids, from every cell around them: finite convex
// weights, no fallback, a few steps (no oscillation). The grid (every cube's corners cospherical)
// and a random cloud whose outer cells are picked too (queries on the hull's triangles).
void queries_on_vertices_edges_and_faces(const ProbeTetWalk& walk, bool with_outer, int count,
                                         int max_steps) {
  const data::ProbeCloud& cloud = walk.cloud();
  std::mt19937 rng(8);
  const auto cells =
      static_cast<std::uint32_t>(with_outer ? cloud.cells.size() : cloud.inner_count);
  std::uniform_int_distribution<std::uint32_t> pick(0, cells - 1);
  for (int n = 0; n < count; ++n) {
    const std::uint32_t t = pick(rng);
    const data::ProbeCell& cell = cloud.cells[t];
    const int corners = cell.outer() ? 3 : 4;
    glm::vec3 v[4];
    for (int k = 0; k < corners; ++k)
      v[k] = cloud.positions[std::size_t(cell.vertices[std::size_t(k)])];
    const glm::vec3 queries[3] = {v[n % corners], 0.5f * (v[0] + v[(n % (corners - 1)) + 1]),
                                  (v[0] + v[1] + v[2]) / 3.0f};
    for (const glm::vec3& q : queries) {
      // From this cell and from each of its neighbours.
      std::int32_t starts[5] = {static_cast<std::int32_t>(t), cell.neighbours[0],
                                cell.neighbours[1], cell.neighbours[2], cell.neighbours[3]};
      for (std::int32_t s : starts) {
        ProbeWalkResult r;
        ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, q, s, &r));
        EXPECT_FALSE(r.fallback);
        EXPECT_LE(r.steps, max_steps);
      }
    }
  }
}

TEST(ProbeTetWalk, QueriesOnVerticesEdgesAndFaces) {
  const auto grid = test::grid_points(10, 10, 10, 1.0f);
  queries_on_vertices_edges_and_faces(
      ProbeTetWalk(make_cloud(grid, test::random_sh(grid.size(), 3, 7))), false, 150, 8);
  const auto points = test::random_points(300, 10.0f, 27);
  ProbeWalkSettings no_far;  // hull triangles of a random cloud are larger than the far check
  no_far.far_cells = 1e9f;
  queries_on_vertices_edges_and_faces(
      ProbeTetWalk(make_cloud(points, test::random_sh(points.size(), 3, 28)), no_far), true, 150,
      16);  // from an outer cell p is behind: into its tetrahedron, then across hull slivers (<=
            // 13)
}

TEST(ProbeTetWalk, InterpolationAtAProbeIsThatProbeExactly) {
  const auto points = test::random_points(200, 10.0f, 9);
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 3, 10)));
  const data::ProbeCloud& cloud = walk.cloud();
  const std::size_t n = 9;
  std::int32_t cached = -1;
  for (std::size_t k = 0; k < cloud.probe_count(); ++k) {
    const ProbeWalkResult r = walk.locate(cloud.positions[k], cached);
    cached = r.cell;
    const ProbeSh s = walk.interpolate(r);
    for (std::size_t ch = 0; ch < 3; ++ch)
      for (std::size_t i = 0; i < 16; ++i)
        ASSERT_EQ(s[ch][i], i < n ? cloud.probe_sh(k)[ch * n + i] : 0.0f)
            << "probe " << k << " channel " << ch << " coefficient " << i;
  }
}

// Barycentric interpolation of an affine function is exact (to float rounding) inside the hull.
TEST(ProbeTetWalk, AffineShFieldIsReproducedInsideTheHull) {
  for (int bands : {2, 3, 4}) {
    const auto points = test::random_points(150, 10.0f, 11);
    const ProbeTetWalk walk(make_cloud(points, test::affine_sh(points, bands), bands));
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> u(0.0f, 10.0f);
    std::int32_t cached = -1;
    int inside = 0;
    for (int q = 0; q < 2000; ++q) {
      const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, u);
      const ProbeWalkResult r = walk.locate(p, cached);
      cached = r.cell;
      if (static_cast<std::uint32_t>(r.cell) >= walk.cloud().inner_count) continue;
      ++inside;
      const ProbeSh s = walk.interpolate(r);
      const std::size_t n = static_cast<std::size_t>(bands * bands);
      for (std::size_t ch = 0; ch < 3; ++ch)
        for (std::size_t i = 0; i < 16; ++i) {
          const float want = i < n ? test::affine_coeff(p, ch, i) : 0.0f;
          ASSERT_NEAR(s[ch][i], want, 2e-5f * (1.0f + std::fabs(want)))
              << "bands " << bands << " query " << q;
        }
    }
    EXPECT_GT(inside, 1000);
  }
}

// An entity walking out of the hull and far away: an outer cell, convex weights, and a value
// between the probes' smallest and largest (never black, never overbright).
TEST(ProbeTetWalk, LeavingTheHullEndsInAnOuterCellWithBoundedValues) {
  PENUMBRA_STABILITY("an entity walking out of the hull and far away",
                     "an outer cell, convex weights: never black, never overbright", "-");
  const auto points = test::random_points(200, 10.0f, 13);
  const auto sh = test::random_sh(points.size(), 3, 14);
  const ProbeTetWalk walk(make_cloud(points, sh));
  const data::ProbeCloud& cloud = walk.cloud();
  float lo[3], hi[3];
  for (std::size_t ch = 0; ch < 3; ++ch) {
    lo[ch] = std::numeric_limits<float>::max();
    hi[ch] = -lo[ch];
    for (std::size_t k = 0; k < cloud.probe_count(); ++k) {
      lo[ch] = std::min(lo[ch], cloud.probe_sh(k)[ch * 9]);
      hi[ch] = std::max(hi[ch], cloud.probe_sh(k)[ch * 9]);
    }
  }
  for (const glm::vec3& dir : {glm::vec3(1, 0.2f, 0.1f), glm::vec3(-0.3f, -1, 0.5f),
                               glm::vec3(0.1f, 0.1f, 1), glm::vec3(-1, -1, -1)}) {
    std::int32_t cached = -1;
    const glm::vec3 d = glm::normalize(dir);
    for (float s = 0; s < 200.0f; s += 0.25f) {
      const glm::vec3 p = glm::vec3(5.0f) + s * d;
      ProbeWalkResult r;
      ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, p, cached, &r));
      cached = r.cell;
      if (s > 20.0f) {
        ASSERT_GE(static_cast<std::uint32_t>(r.cell), cloud.inner_count) << "s = " << s;
        EXPECT_EQ(r.weights[3], 0.0f);
      }
      const ProbeSh v = walk.interpolate(r);
      for (std::size_t ch = 0; ch < 3; ++ch) {
        ASSERT_GE(v[ch][0], lo[ch] - 1e-5f) << "s = " << s;
        ASSERT_LE(v[ch][0], hi[ch] + 1e-5f) << "s = " << s;
      }
    }
  }
}

TEST(ProbeTetWalk, TeleportRunsTheFallbackAndFindsTheRightCell) {
  const auto points = test::random_points(1000, 20.0f, 15);
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 3, 16)));
  const ProbeWalkResult a = walk.locate({10, 10, 10}, -1);
  EXPECT_TRUE(a.fallback);  // no cache
  const ProbeWalkResult b = walk.locate({10.1f, 10.0f, 10.05f}, a.cell);
  EXPECT_FALSE(b.fallback);  // a small move
  ProbeWalkResult c;
  ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, {19, 18, 19}, b.cell, &c));
  EXPECT_TRUE(c.fallback);
  EXPECT_LT(c.steps, 40);
}

TEST(ProbeTetWalk, InvalidStartCellsFallBack) {
  PENUMBRA_STABILITY("invalid start cells (negative, past the end)",
                     "the walk falls back to a located start: the same result", "-");
  const auto points = test::random_points(300, 10.0f, 17);
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 3, 18)));
  const auto other_points = test::random_points(3000, 50.0f, 19);
  const auto other = make_cloud(other_points, {});
  for (std::int32_t start : {-1, -7, std::numeric_limits<std::int32_t>::max(),
                             static_cast<std::int32_t>(walk.cloud().cells.size()),
                             static_cast<std::int32_t>(other->cells.size() - 1)}) {
    ProbeWalkResult r;
    ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, {4, 5, 6}, start, &r));
  }
}

// A rod of 3 x 3 x 400 probes (1 m): end to end crosses well over 1,000 tetrahedra.
TEST(ProbeTetWalk, CrossingAThousandTetrahedraInOneFrame) {
  const auto points = test::grid_points(3, 3, 400, 1.0f);
  const auto cloud = make_cloud(points, test::random_sh(points.size(), 3, 20));
  ProbeWalkSettings long_walk;
  long_walk.max_steps = 100000;
  long_walk.far_cells = 1e9f;  // no teleport check: walk all the way
  const ProbeTetWalk unlimited(cloud, long_walk);
  const glm::vec3 from(1.2f, 0.7f, 0.5f), to(0.8f, 1.3f, 398.5f);
  const ProbeWalkResult a = unlimited.locate(from, -1);
  const ProbeWalkResult full = unlimited.locate(to, a.cell);
  EXPECT_FALSE(full.fallback);
  EXPECT_GE(full.steps, 1000);
  ProbeWalkSettings capped = long_walk;
  capped.max_steps = 64;
  const ProbeTetWalk walk(cloud, capped);
  ProbeWalkResult r;
  ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, to, a.cell, &r));
  EXPECT_TRUE(r.fallback);  // the cap, then the grid
  EXPECT_LT(r.steps, 64 + 64);
  EXPECT_LT(max_abs_diff(walk.interpolate(r), unlimited.interpolate(full)), 1e-5f);
  // With the default settings the far check sends it to the grid at once.
  const ProbeTetWalk defaults(cloud);
  const ProbeWalkResult d = defaults.locate(to, a.cell);
  EXPECT_TRUE(d.fallback);
  EXPECT_LT(d.steps, 64);
}

TEST(ProbeTetWalk, CloudsWithoutCellsUseTheNearestProbe) {
  // 0 probes: zero SH.
  {
    const ProbeTetWalk walk(make_cloud({}, {}));
    const ProbeWalkResult r = walk.locate({1, 2, 3}, -1);
    EXPECT_EQ(r.cell, kNoCell);
    EXPECT_TRUE(r.fallback);
    const ProbeSh s = walk.interpolate(r);
    for (const auto& ch : s)
      for (float v : ch) EXPECT_EQ(v, 0.0f);
  }
  // 1, 2, 3 probes and 4 coplanar ones: the nearest probe's SH.
  const std::vector<glm::vec3> all = {{0, 0, 0}, {5, 0, 0}, {0, 5, 0}, {5, 5, 0}};
  for (std::size_t n = 1; n <= 4; ++n) {
    const std::vector<glm::vec3> points(all.begin(), all.begin() + static_cast<long>(n));
    const auto sh = test::random_sh(n, 3, 21);
    const ProbeTetWalk walk(make_cloud(points, sh));
    ASSERT_EQ(walk.cloud().inner_count, 0u);
    for (std::size_t k = 0; k < n; ++k) {
      const ProbeWalkResult r = walk.locate(all[k] + glm::vec3(0.5f, 0.5f, 3.0f), 5);
      EXPECT_EQ(r.cell, kNoCell);
      EXPECT_EQ(r.probes[0], static_cast<std::int32_t>(k));
      EXPECT_EQ(r.weights[0], 1.0f);
      EXPECT_EQ(walk.interpolate(r)[1][4], walk.cloud().probe_sh(k)[9 + 4]);
    }
  }
}

TEST(ProbeTetWalk, NonFinitePointsAndBadCloudsAreRejected) {
  PENUMBRA_STABILITY("a non-finite query point; a broken cloud; no cloud",
                     "std::invalid_argument naming the cell or the point", "-");
  const auto points = test::random_points(50, 10.0f, 22);
  const ProbeTetWalk walk(make_cloud(points, {}));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const glm::vec3& p : {glm::vec3(nan, 0, 0), glm::vec3(0, inf, 0), glm::vec3(0, 0, -inf)}) {
    try {
      (void)walk.locate(p, 0);
      ADD_FAILURE() << "no throw";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
    }
  }
  auto bad = std::make_shared<data::ProbeCloud>(*walk.cloud_ptr());
  bad->cells[3].neighbours[1] = static_cast<std::int32_t>(bad->cells.size()) + 5;
  try {
    ProbeTetWalk w(bad);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cell 3: neighbour"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ProbeTetWalk(nullptr), std::invalid_argument);
}

TEST(ProbeTetWalk, BatchEqualsOneByOne) {
  const auto points = test::random_points(400, 10.0f, 23);
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 3, 24)));
  const auto queries = test::random_points(500, 12.0f, 25);
  std::vector<std::int32_t> cells(queries.size(), -1);
  std::vector<ProbeSh> out(queries.size());
  EXPECT_EQ(walk.locate_batch(queries, cells, out), queries.size());  // no cache: all fall back
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const ProbeWalkResult r = walk.locate(queries[i], -1);
    EXPECT_EQ(cells[i], r.cell);
    EXPECT_EQ(max_abs_diff(out[i], walk.interpolate(r)), 0.0f);
  }
  EXPECT_EQ(walk.locate_batch(queries, cells, out), 0u);  // from the found cells: no fallback
  std::vector<ProbeSh> short_out(3);
  EXPECT_THROW(walk.locate_batch(queries, cells, short_out), std::invalid_argument);
  // At 3 and 2 bands: the same cells, the same coefficients, bit for bit.
  std::vector<std::int32_t> cells3(queries.size(), -1), cells2(queries.size(), -1);
  std::vector<sh::CoeffsRgb<3>> out3(queries.size());
  std::vector<sh::CoeffsRgb<2>> out2(queries.size());
  EXPECT_EQ(walk.locate_batch(queries, cells3, out3), queries.size());
  EXPECT_EQ(walk.locate_batch(queries, cells2, out2), queries.size());
  EXPECT_EQ(cells3, cells);
  EXPECT_EQ(cells2, cells);
  for (std::size_t i = 0; i < queries.size(); ++i)
    for (std::size_t ch = 0; ch < 3; ++ch) {
      for (std::size_t k = 0; k < 9; ++k) ASSERT_EQ(out3[i][ch][k], out[i][ch][k]);
      for (std::size_t k = 0; k < 4; ++k) ASSERT_EQ(out2[i][ch][k], out[i][ch][k]);
    }
}

// interpolate at fewer or more bands than the cloud's: the same coefficients as at 4 bands where
// both have them, zero past the cloud's.
TEST(ProbeTetWalk, InterpolationAtOtherBandsKeepsTheCommonCoefficients) {
  const auto points = test::random_points(200, 10.0f, 26);
  const auto queries = test::random_points(100, 12.0f, 27);
  for (int bands = 2; bands <= 4; ++bands) {
    const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), bands, 28), bands));
    for (const glm::vec3& q : queries) {
      const ProbeWalkResult r = walk.locate(q, -1);
      const ProbeSh full = walk.interpolate(r);
      ProbeSh four;
      sh::CoeffsRgb<3> three;
      sh::CoeffsRgb<2> two;
      walk.interpolate(r, four);
      walk.interpolate(r, three);
      walk.interpolate(r, two);
      const std::size_t n = static_cast<std::size_t>(bands * bands);
      for (std::size_t ch = 0; ch < 3; ++ch) {
        for (std::size_t k = 0; k < 16; ++k) {
          ASSERT_EQ(four[ch][k], full[ch][k]);
          if (k >= n) {
            ASSERT_EQ(full[ch][k], 0.0f);
          }
        }
        for (std::size_t k = 0; k < 9; ++k) ASSERT_EQ(three[ch][k], full[ch][k]) << bands;
        for (std::size_t k = 0; k < 4; ++k) ASSERT_EQ(two[ch][k], full[ch][k]) << bands;
      }
    }
  }
}

// at(cell, p) rebuilds what locate(p) returned when it found cell (inside, outside the hull, on
// probes, after the fallback; a cloud without cells).
TEST(ProbeTetWalk, AtRebuildsTheLocateResult) {
  const auto points = test::random_points(300, 10.0f, 29);
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 3, 30)));
  auto queries = test::random_points(500, 13.0f, 31);
  queries.insert(queries.end(), points.begin(), points.begin() + 20);
  for (const glm::vec3& q : queries) {
    const ProbeWalkResult r = walk.locate(q, -1);
    const ProbeWalkResult a = walk.at(r.cell, q);
    ASSERT_EQ(a.cell, r.cell);
    ASSERT_EQ(a.probes, r.probes);
    ASSERT_EQ(a.weights, r.weights);
  }
  const ProbeTetWalk few(make_cloud({{0, 0, 0}, {5, 0, 0}}, test::random_sh(2, 3, 32)));
  const ProbeWalkResult r = few.locate({4, 1, 0}, -1);
  EXPECT_EQ(few.at(r.cell, {4, 1, 0}).probes, r.probes);
  EXPECT_EQ(few.at(r.cell, {4, 1, 0}).weights, r.weights);
}

// 10 km from the origin at 1 m spacing (godotengine/godot #82642: a float epsilon broke 100 m
// scenes): p - p3 is exact there (Sterbenz), so the walk is as sure as near the origin.
TEST(ProbeTetWalk, FarFromTheOriginAtOneMetreSpacing) {
  auto points = test::grid_points(8, 8, 8, 1.0f);
  const glm::vec3 offset(10000.0f, -10000.0f, 300.0f);
  for (glm::vec3& p : points) p += offset;
  const ProbeTetWalk walk(make_cloud(points, test::affine_sh(points, 3)));
  ASSERT_GT(walk.cloud().inner_count, 0u);
  std::mt19937 rng(26);
  std::uniform_real_distribution<float> u(-1.0f, 8.0f), jitter(-0.2f, 0.2f);
  std::int32_t cached = -1;
  glm::vec3 p = offset + glm::vec3(3.5f);
  int fallbacks = 0;
  for (int i = 0; i < 600; ++i) {
    p = (i % 10 == 0) ? offset + penumbra::test::draw_zyx<glm::vec3>(rng, u)
                      : p + penumbra::test::draw_zyx<glm::vec3>(rng, jitter);
    ProbeWalkResult r;
    ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, p, cached, &r));
    cached = r.cell;
    fallbacks += (i % 10 != 0 && r.fallback) ? 1 : 0;
  }
  EXPECT_LE(fallbacks, 5);  // small moves walk
}

// A 1 km strip at 1 m spacing plus 10 probes 100 m apart (godotengine/godot #82642's scene):
// a very uneven cloud, whose grid is coarse for the strip; entities along the strip and among the
// far probes still land in the right cell.
TEST(ProbeTetWalk, KilometreStripWithSparseProbes) {
  std::vector<glm::vec3> points;
  const glm::vec3 origin(4000.0f, -2000.0f, 500.0f);
  for (int x = 0; x < 1000; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 2; ++z)
        points.push_back(origin + glm::vec3(float(x), float(y), float(z)));
  for (int k = 0; k < 10; ++k)
    points.push_back(origin + glm::vec3(100.0f * float(k) + 37.0f, 60.0f + 7.0f * float(k % 3),
                                        40.0f + 11.0f * float(k % 4)));
  const ProbeTetWalk walk(make_cloud(points, test::random_sh(points.size(), 2, 29), 2));
  ASSERT_GT(walk.cloud().inner_count, 0u);
  std::mt19937 rng(30);
  std::uniform_real_distribution<float> ux(-50.0f, 1050.0f), uy(-5.0f, 80.0f), uz(-5.0f, 60.0f),
      jitter(-0.5f, 0.5f);
  std::int32_t cached = -1;
  glm::vec3 p = origin + glm::vec3(500.0f, 1.0f, 0.5f);
  for (int i = 0; i < 120; ++i) {
    p = (i % 4 == 0) ? origin + penumbra::test::draw_zyx<glm::vec3>(rng, ux, uy, uz)
                     : p + penumbra::test::draw_zyx<glm::vec3>(rng, jitter);
    ProbeWalkResult r;
    ASSERT_NO_FATAL_FAILURE(check_against_brute_force(walk, p, cached, &r));
    cached = r.cell;
  }
}

TEST(ProbeTetWalk, PathListsTheCellsVisited) {
  const auto points = test::grid_points(6, 6, 6, 1.0f);
  ProbeWalkSettings settings;
  settings.far_cells = 1e9f;  // walk, no teleport fallback
  const ProbeTetWalk walk(make_cloud(points, {}), settings);
  const ProbeWalkResult a = walk.locate({0.5f, 0.5f, 0.5f}, -1);
  std::vector<std::int32_t> path;
  const ProbeWalkResult b = walk.locate({2.5f, 1.5f, 1.2f}, a.cell, &path);
  ASSERT_FALSE(path.empty());
  EXPECT_EQ(path.front(), a.cell);
  EXPECT_EQ(path.back(), b.cell);
  EXPECT_FALSE(b.fallback);
  EXPECT_EQ(static_cast<int>(path.size()), b.steps + 1);
}

}  // namespace
}  // namespace penumbra::probe_cloud
