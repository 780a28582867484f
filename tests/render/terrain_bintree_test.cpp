#include "penumbra/render/terrain_bintree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "common/stability.h"
#include "render_test_util.h"

namespace penumbra::render {
namespace {

data::HeightField field(int w, int h, float cell, float (*height)(int, int)) {
  data::HeightField f;
  f.width = w;
  f.height = h;
  f.cell_size = cell;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) f.heights.push_back(height(x, y));
  return f;
}

float hills(int x, int y) {
  return 1.5f * std::sin(0.35f * static_cast<float>(x)) * std::cos(0.25f * static_cast<float>(y)) +
         0.05f * static_cast<float>(x);
}

struct Mesh {
  std::vector<glm::ivec2> corners;  // 3 per triangle
};

Mesh mesh(const TerrainBintree& tree, const data::HeightField& f,
          const TerrainBintree::View& view) {
  std::vector<std::uint32_t> indices;
  const std::size_t n = tree.triangulate(view, indices);
  EXPECT_EQ(indices.size(), 3 * n);
  Mesh m;
  for (std::uint32_t i : indices)
    m.corners.emplace_back(static_cast<int>(i) % f.width, static_cast<int>(i) / f.width);
  return m;
}

long long twice_area(glm::ivec2 a, glm::ivec2 b, glm::ivec2 c) {
  return static_cast<long long>(b.x - a.x) * (c.y - a.y) -
         static_cast<long long>(b.y - a.y) * (c.x - a.x);
}

// Every triangle counter-clockwise from above, their areas summing to the grid's, and no vertex
// inside another triangle's edge (no T-junction): the mesh covers the grid without crack.
void expect_conforming_cover(const Mesh& m, const data::HeightField& f) {
  std::set<std::pair<int, int>> vertices;
  for (const glm::ivec2& v : m.corners) vertices.insert({v.x, v.y});
  long long area = 0;
  int t_junctions = 0;
  for (std::size_t t = 0; t < m.corners.size(); t += 3) {
    const glm::ivec2 a = m.corners[t], b = m.corners[t + 1], c = m.corners[t + 2];
    const long long twice = twice_area(a, b, c);
    ASSERT_GT(twice, 0) << "triangle " << t / 3 << " is not counter-clockwise";
    area += twice;
    for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      const glm::ivec2 d = q - p;
      const int steps = std::max(std::abs(d.x), std::abs(d.y));
      const glm::ivec2 step = d / steps;  // edges run along axes or diagonals
      for (int k = 1; k < steps; ++k) {
        const glm::ivec2 v = p + k * step;
        t_junctions += vertices.count({v.x, v.y}) > 0;
      }
    }
  }
  EXPECT_EQ(area, 2LL * (f.width - 1) * (f.height - 1));
  EXPECT_EQ(t_junctions, 0);
}

TerrainBintree::View uncull(float max_pixels, glm::vec3 eye = {0.0f, 0.0f, 50.0f}) {
  TerrainBintree::View v;
  v.cull = false;
  v.eye = eye;
  v.focal_px = 500.0f;
  v.max_pixels = max_pixels;
  return v;
}

TEST(TerrainBintree, FullDetailDrawsEveryCellOnAnyGridSize) {
  for (const auto& [w, h] : {std::pair{33, 33}, std::pair{20, 20}, std::pair{40, 17},
                             std::pair{2, 2}, std::pair{2, 9}}) {
    const data::HeightField f = field(w, h, 1.0f, hills);
    TerrainBintree tree;
    tree.build(f);
    const Mesh m = mesh(tree, f, uncull(0.0f));
    EXPECT_EQ(m.corners.size(), 6u * (w - 1) * (h - 1)) << w << "x" << h;
    expect_conforming_cover(m, f);
  }
}

TEST(TerrainBintree, APlaneIsTwoTriangles) {
  const data::HeightField f =
      field(33, 33, 2.0f, [](int x, int y) { return 0.3f * x - 0.2f * y + 1.0f; });
  TerrainBintree tree;
  tree.build(f);
  EXPECT_NEAR(tree.error(16, 16), 0.0f, 1e-4f);  // float rounding: not exactly 0
  const Mesh m = mesh(tree, f, uncull(1.0f, {0.0f, 0.0f, 1000.0f}));
  EXPECT_EQ(m.corners.size(), 6u);
  expect_conforming_cover(m, f);
  // Off the 2^k + 1 sizes the border splits, but a plane still needs no more inside.
  const data::HeightField g =
      field(30, 21, 2.0f, [](int x, int y) { return 0.3f * x - 0.2f * y + 1.0f; });
  tree.build(g);
  EXPECT_EQ(tree.error(16, 16), std::numeric_limits<float>::infinity()) << "across the border";
  expect_conforming_cover(mesh(tree, g, uncull(1.0f)), g);
}

// The triangles drawn, at any budget and eye, cover the grid without T-junctions.
TEST(TerrainBintree, CoversTheGridWithoutCracksAtAnyBudget) {
  for (const auto& [w, h] : {std::pair{65, 65}, std::pair{50, 37}}) {
    const data::HeightField f = field(w, h, 1.0f, hills);
    TerrainBintree tree;
    tree.build(f);
    for (float budget : {0.5f, 2.0f, 8.0f, 64.0f})
      for (const glm::vec3 eye : {glm::vec3(10, 10, 5), glm::vec3(-30, 20, 40)}) {
        SCOPED_TRACE(testing::Message() << w << "x" << h << " budget " << budget);
        expect_conforming_cover(mesh(tree, f, uncull(budget, eye)), f);
      }
  }
}

// Each triangle drawn: its largest vertical distance to a sample inside it, seen from the eye
// anywhere on the triangle, spans at most the budget. Checked independently of the class: the
// error by enumerating samples, its projection by sampling the triangle densely.
TEST(TerrainBintree, EveryTriangleIsWithinThePixelBudget) {
  const data::HeightField f = field(65, 65, 0.5f, hills);
  TerrainBintree tree;
  tree.build(f);
  const float budget = 2.0f;
  const glm::vec3 eye(-4.0f, 6.0f, 3.0f);
  const Mesh m = mesh(tree, f, uncull(budget, eye));
  auto position = [&](float x, float y, float h) { return glm::vec3(x * 0.5f, y * 0.5f, h); };
  auto height = [&](int x, int y) { return f.heights[static_cast<std::size_t>(y) * f.width + x]; };
  int checked = 0, over = 0;
  for (std::size_t t = 0; t < m.corners.size(); t += 3) {
    const glm::ivec2 a = m.corners[t], b = m.corners[t + 1], c = m.corners[t + 2];
    const glm::vec3 pa = position(a.x, a.y, height(a.x, a.y));
    const glm::vec3 pb = position(b.x, b.y, height(b.x, b.y));
    const glm::vec3 pc = position(c.x, c.y, height(c.x, c.y));
    double error = 0;
    for (int y = std::min({a.y, b.y, c.y}); y <= std::max({a.y, b.y, c.y}); ++y)
      for (int x = std::min({a.x, b.x, c.x}); x <= std::max({a.x, b.x, c.x}); ++x) {
        const glm::ivec2 p(x, y);
        const long long w0 = twice_area(a, b, p), w1 = twice_area(b, c, p),
                        w2 = twice_area(c, a, p);
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const double total = static_cast<double>(w0 + w1 + w2);
        const double plane = (w1 * pa.z + w2 * pb.z + w0 * pc.z) / total;
        error = std::max(error, std::abs(height(x, y) - plane));
      }
    // Pixels per unit of vertical error at p: focal * h / |p - eye|^2 (h horizontal distance).
    float worst = 0;
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; i + j <= 40; ++j) {
        const glm::vec3 v = pa + i / 40.0f * (pb - pa) + j / 40.0f * (pc - pa) - eye;
        worst = std::max(worst, 500.0f * std::hypot(v.x, v.y) / glm::dot(v, v));
      }
    ++checked;
    over += error * worst > budget * 1.0001 + 1e-6;
  }
  EXPECT_GT(checked, 50);
  EXPECT_LT(checked, 2 * 64 * 64 / 2) << "the budget coarsens";
  EXPECT_EQ(TerrainBintree::projected_pixels(1.0f, eye, 0.5f, uncull(1.0f, eye)),
            std::numeric_limits<float>::infinity())
      << "the eye in the sphere";
  EXPECT_EQ(over, 0);
}

// Far away, fewer and larger triangles; a view that looks away from the grid culls it all.
TEST(TerrainBintree, CoarsensWithDistanceAndCullsOutsideTheView) {
  const data::HeightField f = field(129, 129, 1.0f, hills);
  TerrainBintree tree;
  tree.build(f);
  const Mesh near = mesh(tree, f, uncull(1.0f, {64, 64, 10}));
  const Mesh far = mesh(tree, f, uncull(1.0f, {64, 64, 1000}));
  EXPECT_GT(near.corners.size(), 4 * far.corners.size());
  TerrainBintree::View view = uncull(1.0f, {-10.0f, -10.0f, 5.0f});
  view.cull = true;
  const glm::mat4 proj = glm::perspective(0.8f, 1.5f, 0.1f, 1000.0f);
  view.view_proj = proj * glm::lookAt(view.eye, glm::vec3(-50, -50, 0), glm::vec3(0, 0, 1));
  std::vector<std::uint32_t> indices;
  EXPECT_EQ(tree.triangulate(view, indices), 0u) << "looking away";
  view.view_proj = proj * glm::lookAt(view.eye, glm::vec3(64, 64, 0), glm::vec3(0, 0, 1));
  const std::size_t seen = tree.triangulate(view, indices);
  EXPECT_GT(seen, 0u);
  EXPECT_LT(seen, tree.triangulate(uncull(1.0f, view.eye), indices)) << "the sides are culled";
}

TEST(TerrainBintree, DegenerateFieldsGiveAnEmptyMeshOrSkipBadSamples) {
  PENUMBRA_STABILITY(
      "a 1-wide field; heights shorter than the grid; a NaN sample",
      "no triangles; no triangles; the NaN's cells skipped, the rest a conforming cover", "-");
  TerrainBintree tree;
  std::vector<std::uint32_t> indices;
  tree.build(field(1, 5, 1.0f, hills));
  EXPECT_EQ(tree.triangulate(uncull(1.0f), indices), 0u);
  data::HeightField short_of_heights = field(8, 8, 1.0f, hills);
  short_of_heights.heights.resize(10);
  tree.build(short_of_heights);
  EXPECT_EQ(tree.triangulate(uncull(1.0f), indices), 0u);
  data::HeightField with_nan = field(17, 17, 1.0f, hills);
  with_nan.heights[5 * 17 + 7] = std::numeric_limits<float>::quiet_NaN();
  tree.build(with_nan);
  expect_conforming_cover(mesh(tree, with_nan, uncull(1.0f)), with_nan);
}

}  // namespace
}  // namespace penumbra::render
