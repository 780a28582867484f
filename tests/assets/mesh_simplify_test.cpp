#include "penumbra/assets/mesh_simplify.h"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include "common/stability.h"
#include "test_meshes.h"

namespace penumbra::assets {
namespace {

std::set<std::tuple<float, float, float>> position_set(const data::MeshData& m) {
  std::set<std::tuple<float, float, float>> s;
  for (const glm::vec3& p : m.positions) s.insert({p.x, p.y, p.z});
  return s;
}

// A flat n x n grid of quads on z = 0 (2 n^2 triangles).
data::MeshData flat_grid(int n) {
  data::MeshData m;
  m.name = "grid";
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.positions.push_back({x, y, 0});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  return m;
}

TEST(MeshSimplify, KeepsOriginalVerticesWithinTheErrorBound) {
  data::MeshData ball = test::icosphere(4);  // 5,120 triangles
  ball.normals = ball.positions;             // the normals travel with their vertices
  const SimplifiedMesh s = simplify_mesh(ball, {0.1f, 0.05f});
  const std::size_t triangles = s.mesh.indices.size() / 3;
  EXPECT_LE(triangles, 512u);
  EXPECT_GT(triangles, 20u);
  EXPECT_LE(s.error, 0.05f);
  ASSERT_EQ(s.mesh.normals.size(), s.mesh.positions.size());
  const auto original = position_set(ball);
  std::set<std::uint32_t> used;
  for (const std::uint32_t i : s.mesh.indices) {
    ASSERT_LT(i, s.mesh.positions.size());
    used.insert(i);
  }
  EXPECT_EQ(used.size(), s.mesh.positions.size());  // no unused vertex left
  for (std::size_t i = 0; i < s.mesh.positions.size(); ++i) {
    const glm::vec3& p = s.mesh.positions[i];
    EXPECT_TRUE(original.count({p.x, p.y, p.z})) << "vertex " << i << " is not an original one";
    EXPECT_EQ(s.mesh.normals[i], p);  // its own normal (on the unit sphere: the position)
  }
}

TEST(MeshSimplify, ErrorBoundStopsTheCollapses) {
  // A curved surface with no error allowed keeps (nearly) everything; a flat one collapses.
  const SimplifiedMesh curved = simplify_mesh(test::icosphere(3), {0.1f, 0.0f});
  EXPECT_GT(curved.mesh.indices.size(), 0.9 * 1280 * 3);
  const SimplifiedMesh flat = simplify_mesh(flat_grid(16), {0.01f, 0.0f});
  EXPECT_LT(flat.mesh.indices.size() / 3, 64u);  // of 512
  EXPECT_LE(flat.error, 1e-5f);
}

TEST(MeshSimplify, BadInputIsNamed) {
  PENUMBRA_STABILITY("an empty mesh; ratio 0 or above 1", "std::invalid_argument naming the reason",
                     "-");
  data::MeshData empty;
  empty.name = "nothing";
  try {
    simplify_mesh(empty);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nothing"), std::string::npos) << e.what();
  }
  data::MeshData bad = test::icosphere(1);
  bad.indices[5] = 100000;
  EXPECT_THROW(simplify_mesh(bad), std::invalid_argument);
  EXPECT_THROW(simplify_mesh(test::icosphere(1), {0.0f, 0.01f}), std::invalid_argument);
  EXPECT_THROW(simplify_mesh(test::icosphere(1), {1.5f, 0.01f}), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::assets
