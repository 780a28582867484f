#include "penumbra/systems/probe_cloud/cell_weights.h"

#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/random_draws.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

namespace penumbra::probe_cloud {
namespace {

data::ProbeCloud grid_cloud(int n, float spacing) {
  std::vector<glm::vec3> p;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) p.push_back(glm::vec3(i, j, k) * spacing);
  return build_probe_cloud(p, {});
}

// The cell containing p (all weights >= -tol) by brute force.
int find_cell(const data::ProbeCloud& cloud, const glm::vec3& p, float tol = 1e-5f) {
  for (std::uint32_t c = 0; c < cloud.cells.size(); ++c) {
    const auto w = cell_weights(cloud, c, p);
    if (w[0] >= -tol && w[1] >= -tol && w[2] >= -tol && w[3] >= -tol) return int(c);
  }
  return -1;
}

TEST(CellWeights, InnerWeightsAreBarycentric) {
  const data::ProbeCloud cloud = grid_cloud(3, 1.0f);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.05f, 1.95f);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, u);
    const int c = find_cell(cloud, p);
    ASSERT_GE(c, 0);
    ASSERT_LT(std::uint32_t(c), cloud.inner_count);
    const auto w = cell_weights(cloud, std::uint32_t(c), p);
    glm::vec3 back(0.0f);
    for (int k = 0; k < 4; ++k) back += w[k] * cloud.positions[cloud.cells[c].vertices[k]];
    EXPECT_NEAR(glm::length(back - p), 0.0f, 1e-5f);
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0f, 1e-6f);
  }
}

TEST(CellWeights, OuterCellsCoverTheOutsideWithConvexWeights) {
  // A flat grid face (equal normals: the cubic drops to linear), edges and corners (diverging
  // normals: a real cubic).
  const data::ProbeCloud cloud = grid_cloud(3, 1.0f);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-3.0f, 5.0f);
  int outside = 0;
  for (int i = 0; i < 300; ++i) {
    const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, u);
    const bool inside = p.x > 0 && p.x < 2 && p.y > 0 && p.y < 2 && p.z > 0 && p.z < 2;
    if (inside) continue;
    ++outside;
    const int c = find_cell(cloud, p, 1e-4f);
    ASSERT_GE(c, 0) << p.x << " " << p.y << " " << p.z;
    EXPECT_GE(std::uint32_t(c), cloud.inner_count);
    const auto w = cell_weights(cloud, std::uint32_t(c), p);
    EXPECT_NEAR(w[0] + w[1] + w[2], 1.0f, 1e-4f);
    EXPECT_EQ(w[3], 0.0f);
    const auto cw = convex_weights(w);
    for (float v : cw) {
      EXPECT_GE(v, 0.0f);
      EXPECT_LE(v, 1.0f);
    }
    EXPECT_NEAR(cw[0] + cw[1] + cw[2] + cw[3], 1.0f, 1e-6f);
    EXPECT_GE(outer_cell_parameter(cloud, std::uint32_t(c), p), 0.0);
  }
  EXPECT_GT(outside, 100);
}

TEST(CellWeights, FlatFaceIsPlainProjection) {
  // Below the middle of the z = 0 face of a 4^3 grid: the probes there all have the normal
  // (0, 0, -1), so the cubic's t^3 and t^2 terms vanish and t is the distance.
  const data::ProbeCloud cloud = grid_cloud(4, 1.0f);
  const glm::vec3 p(1.5f, 1.25f, -4.0f);
  const int c = find_cell(cloud, p);
  ASSERT_GE(c, 0);
  EXPECT_NEAR(outer_cell_parameter(cloud, std::uint32_t(c), p), 4.0, 1e-9);
  const auto w = cell_weights(cloud, std::uint32_t(c), p);
  glm::vec3 back(0.0f);
  for (int k = 0; k < 3; ++k) back += w[k] * cloud.positions[cloud.cells[c].vertices[k]];
  EXPECT_NEAR(back.x, 1.5f, 1e-5f);
  EXPECT_NEAR(back.y, 1.25f, 1e-5f);
}

TEST(CellWeights, InnerSideOfAHullFacePointsToTheTetrahedron) {
  const data::ProbeCloud cloud = grid_cloud(2, 1.0f);
  for (std::uint32_t c = cloud.inner_count; c < cloud.cells.size(); ++c) {
    const auto w = cell_weights(cloud, c, glm::vec3(0.5f));  // the cube's centre
    EXPECT_LT(w[3], std::min({w[0], w[1], w[2]}));
    EXPECT_LT(w[3], 0.0f);
  }
}

TEST(CellWeights, OuterTransformHoldsTheCubic) {
  // Row k of an outer cell's transform dotted with (p, 1) is the coefficient of t^(3-k) of
  // det[p0 + t n0 - p, p1 + t n1 - p, p2 + t n2 - p] (data/probe_cloud.h): compare with the
  // determinant evaluated directly at a few t.
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1.0f, 3.0f);
  std::vector<glm::vec3> pts(60);
  for (glm::vec3& q : pts) q = {u(rng), u(rng), u(rng)};
  const data::ProbeCloud cloud = build_probe_cloud(pts, {});
  ASSERT_GT(cloud.cells.size(), cloud.inner_count);
  for (std::uint32_t c = cloud.inner_count; c < cloud.cells.size(); ++c) {
    const glm::mat4& m = cloud.transforms[c];
    const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, u);
    const glm::vec4 k = m * glm::vec4(p, 1.0f);
    const auto& v = cloud.cells[c].vertices;
    for (double t : {0.0, 0.5, 1.0, 2.0}) {
      glm::dvec3 col[3];
      for (int i = 0; i < 3; ++i) {
        col[i] = glm::dvec3(cloud.positions[v[i]]) + t * glm::dvec3(cloud.hull_normals[v[i]]) -
                 glm::dvec3(p);
      }
      const double direct = glm::dot(col[0], glm::cross(col[1], col[2]));
      const double poly = ((double(k[0]) * t + k[1]) * t + k[2]) * t + k[3];
      EXPECT_NEAR(poly, direct, 1e-4 * (1 + std::abs(direct))) << "cell " << c << " t " << t;
    }
  }
}

// The outer cell's t is the smallest root t >= 0 of det[p_i + t n_i - p] (curved hulls: the
// cubic's leading terms do not vanish): the determinant is ~0 at t and keeps f(0)'s sign before.
TEST(CellWeights, OuterParameterIsTheSmallestRootOfTheCubic) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 3.0f), far(-6.0f, 8.0f);
  std::vector<glm::vec3> pts(80);
  for (glm::vec3& q : pts) q = {u(rng), u(rng), u(rng)};
  const data::ProbeCloud cloud = build_probe_cloud(pts, {});
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const glm::vec3 p = penumbra::test::draw_zyx<glm::vec3>(rng, far);
    const int c = find_cell(cloud, p, 1e-4f);
    if (c < 0 || std::uint32_t(c) < cloud.inner_count) continue;
    const double t = outer_cell_parameter(cloud, std::uint32_t(c), p);
    ASSERT_GE(t, 0.0);
    const auto& v = cloud.cells[c].vertices;
    const auto det = [&](double s) {
      glm::dvec3 col[3];
      for (int i = 0; i < 3; ++i)
        col[i] = glm::dvec3(cloud.positions[v[i]]) + s * glm::dvec3(cloud.hull_normals[v[i]]) -
                 glm::dvec3(p);
      return glm::dot(col[0], glm::cross(col[1], col[2]));
    };
    double scale = 0;  // the determinant's size near t, for a relative tolerance
    for (double s : {0.0, t, 2 * t + 1}) scale = std::max(scale, std::abs(det(s)));
    EXPECT_NEAR(det(t), 0.0, 1e-6 * (1 + scale)) << "cell " << c;
    for (int k = 0; k < 50; ++k) {  // no earlier sign change
      const double s = t * k / 50.0;
      EXPECT_GE(det(s) * det(0.0), -1e-9 * (1 + scale * scale)) << "cell " << c << " s " << s;
    }
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(CellWeights, ConvexWeights) {
  const auto a = convex_weights({0.5f, 0.75f, -0.25f, 0.0f});
  EXPECT_FLOAT_EQ(a[0] + a[1] + a[2] + a[3], 1.0f);
  EXPECT_EQ(a[2], 0.0f);
  const auto b = convex_weights({-1.0f, -0.5f, -2.0f, -3.0f});
  EXPECT_EQ(b[1], 1.0f);
}

}  // namespace
}  // namespace penumbra::probe_cloud
