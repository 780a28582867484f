#include "penumbra/systems/probe_cloud/delaunay_tetrahedralization.h"

#include <algorithm>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/random_draws.h"
#include "common/stability.h"
#include "penumbra/systems/probe_cloud/exact_predicates.h"

namespace penumbra::probe_cloud {
namespace {

using V = glm::dvec3;

// Structural and Delaunay checks straight on the tetrahedralization (the cloud-level validation
// has its own tests).
void expect_valid(const std::vector<V>& p, const DelaunayTetrahedralization& d) {
  ASSERT_EQ(d.vertices.size(), d.neighbours.size());
  std::size_t bad_orient = 0, bad_link = 0, bad_delaunay = 0;
  for (std::size_t c = 0; c < d.vertices.size(); ++c) {
    const auto& v = d.vertices[c];
    const bool ghost = c >= d.finite_count;
    ASSERT_EQ(v[3] == kInfiniteVertex, ghost);
    if (!ghost) bad_orient += orient3d_sign(p[v[0]], p[v[1]], p[v[2]], p[v[3]]) <= 0;
    for (int k = 0; k < 4; ++k) {
      const int nb = d.neighbours[c][k];
      ASSERT_GE(nb, 0);
      const auto& back = d.neighbours[static_cast<std::size_t>(nb)];
      const auto it = std::find(back.begin(), back.end(), static_cast<int>(c));
      if (it == back.end()) {
        ++bad_link;
        continue;
      }
      const int j = static_cast<int>(it - back.begin());
      if (!ghost && static_cast<std::size_t>(nb) < d.finite_count) {
        const int apex = d.vertices[static_cast<std::size_t>(nb)][j];
        bad_delaunay += insphere(p[v[0]], p[v[1]], p[v[2]], p[v[3]], p[apex]) > 0;
      }
    }
  }
  EXPECT_EQ(bad_orient, 0u);
  EXPECT_EQ(bad_link, 0u);
  EXPECT_EQ(bad_delaunay, 0u);
}

TEST(DelaunayTetrahedralization, SingleTetrahedron) {
  const std::vector<V> p{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};  // negatively listed
  const auto d = delaunay_tetrahedralize(p);
  EXPECT_EQ(d.finite_count, 1u);
  EXPECT_EQ(d.hull_count(), 4u);
  expect_valid(p, d);
}

TEST(DelaunayTetrahedralization, TooFewOrFlatGivesNothing) {
  PENUMBRA_STABILITY("0-3 points, coplanar or collinear points", "no tetrahedra, no error", "-");
  EXPECT_TRUE(delaunay_tetrahedralize(std::vector<V>{}).vertices.empty());
  EXPECT_TRUE(
      delaunay_tetrahedralize(std::vector<V>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).vertices.empty());
  std::vector<V> plane;
  for (int i = 0; i < 50; ++i) plane.push_back({i % 7, i / 7, 0.0});
  EXPECT_TRUE(delaunay_tetrahedralize(plane).vertices.empty());
  std::vector<V> line;
  for (int i = 0; i < 50; ++i) line.push_back(V(1, 2, 3) * double(i));
  EXPECT_TRUE(delaunay_tetrahedralize(line).vertices.empty());
}

TEST(DelaunayTetrahedralization, RandomPointsAreDelaunayAndLinear) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  for (std::size_t n : {100u, 2000u, 20000u}) {
    std::vector<V> p(n);
    for (V& q : p) q = penumbra::test::draw_zyx<V>(rng, u);
    const auto d = delaunay_tetrahedralize(p);
    expect_valid(p, d);
    // Euler for a triangulated ball: V - E + F - T = 1, with 2F_hull = 3 * hull faces... count
    // the hull instead: every hull face has three hull edges, each shared by two faces.
    const double ratio = double(d.finite_count) / double(n);
    EXPECT_GT(ratio, 5.0) << n;
    EXPECT_LT(ratio, 7.0) << n;
  }
}

TEST(DelaunayTetrahedralization, CubeGridIsCosphericalEverywhere) {
  std::vector<V> p;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 6; ++k) p.push_back(V(i, j, k) * 0.5 + V(1e5, -3e3, 7));
  const auto d = delaunay_tetrahedralize(p);
  expect_valid(p, d);
  // Each of the 125 cubes is split into 5 or 6 tetrahedra; the hull: 6 faces x 25 squares x 2.
  EXPECT_GE(d.finite_count, 125u * 5);
  EXPECT_LE(d.finite_count, 125u * 6);
  EXPECT_EQ(d.hull_count(), 6u * 25 * 2);
  // Deterministic.
  const auto again = delaunay_tetrahedralize(p);
  EXPECT_EQ(again.vertices, d.vertices);
}

TEST(DelaunayTetrahedralization, HullWithCoplanarFacesAndPointsOnThem) {
  // A box whose faces carry extra points (hull faces coplanar) plus interior points.
  std::vector<V> p;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 300; ++i) {
    V q = penumbra::test::draw_zyx<V>(rng, u);
    q[i % 3] = (i / 3) % 2;  // on a face of the unit cube
    p.push_back(q);
  }
  for (int i = 0; i < 8; ++i) p.push_back(V(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  for (int i = 0; i < 100; ++i) p.push_back(penumbra::test::draw_zyx<V>(rng, u));
  const auto d = delaunay_tetrahedralize(p);
  expect_valid(p, d);
  // Hull vertices: every point on the cube's surface is on the hull.
  std::set<int> hull;
  for (std::size_t c = d.finite_count; c < d.vertices.size(); ++c) {
    for (int i = 0; i < 3; ++i) hull.insert(d.vertices[c][i]);
  }
  EXPECT_EQ(hull.size(), 308u);
}

TEST(DelaunayTetrahedralization, DegenerateLatticeSubsets) {
  PENUMBRA_STABILITY("random subsets of a 4x4x4 lattice (coplanar, cospherical, collinear)",
                     "valid, no degenerate hull triangle, volumes add up to the hull's",
                     "exact predicates");
  // Random subsets of a 4x4x4 lattice: coplanar hull faces, cospherical and collinear sets
  // everywhere, hull points inserted after interior ones. Each must be valid and cover the
  // lattice subset's hull (the tetrahedra's volumes add up to the hull's).
  std::mt19937 rng(17);
  for (int round = 0; round < 200; ++round) {
    std::vector<V> p;
    const int keep = 5 + int(rng() % 60);
    for (int i = 0; i < 64; ++i) {
      if (int(rng() % 64) < keep) p.push_back(V(i & 3, (i >> 2) & 3, (i >> 4) & 3));
    }
    std::shuffle(p.begin(), p.end(), rng);
    const auto d = delaunay_tetrahedralize(p);
    if (d.vertices.empty()) continue;
    expect_valid(p, d);
    double tets = 0, hull = 0;
    for (std::size_t c = 0; c < d.vertices.size(); ++c) {
      const auto& v = d.vertices[c];
      if (c < d.finite_count) {
        tets += orient3d(p[v[0]], p[v[1]], p[v[2]], p[v[3]]);
      } else {
        hull += orient3d(V(0.0), p[v[0]], p[v[1]], p[v[2]]);
        // No degenerate hull triangle (exact on small integers).
        const V n = glm::cross(p[v[1]] - p[v[0]], p[v[2]] - p[v[0]]);
        ASSERT_NE(glm::dot(n, n), 0.0) << "round " << round << " hull cell " << c;
      }
    }
    ASSERT_NEAR(tets, hull, 1e-9) << "round " << round;
    if (HasFailure()) break;
  }
}

}  // namespace
}  // namespace penumbra::probe_cloud
