#include <gtest/gtest.h>

#include "common/stability.h"
#include "gltf_builder.h"
#include "penumbra/assets/gltf.h"
#include "test_support.h"

namespace penumbra::assets {
namespace {

using test::expect_error;
using test::GltfDoc;
using test::load;

glm::vec3 apply(const glm::mat4& m, glm::vec3 p) {
  return glm::vec3(m * glm::vec4(p, 1.0f));
}

void expect_near(glm::vec3 a, glm::vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST(GltfNodes, YUpBecomesZUp) {
  expect_near(apply(gltf_to_engine(), {0, 1, 0}), {0, 0, 1});
  expect_near(apply(gltf_to_engine(), {0, 0, 1}), {0, -1, 0});
  expect_near(apply(gltf_to_engine(), {1, 0, 0}), {1, 0, 0});
}
TEST(GltfNodes, NodeHierarchyComposesTrsAndMatrices) {
  GltfDoc d = GltfDoc::triangle();
  // node 0: translate (1, 2, 3); node 1 (child): rotate 90 deg about z, scale 2; node 2 (child
  // of 1): matrix translating by (0, 0, 5); meshes on nodes 1 and 2.
  const float s = std::sqrt(0.5f);
  d.j["nodes"] = {
      {{"translation", {1, 2, 3}}, {"children", {1}}},
      {{"rotation", {0, 0, s, s}}, {"scale", {2, 2, 2}}, {"mesh", 0}, {"children", {2}}},
      {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}, {"mesh", 0}}};
  const Model m = load(d);
  ASSERT_EQ(m.instances.size(), 2u);
  EXPECT_EQ(m.node_count, 3u);
  const glm::mat4 g = gltf_to_engine();
  // (1, 0, 0) -> scale (2, 0, 0) -> rotate (0, 2, 0) -> translate (1, 4, 3) -> z-up (1, -3, 4).
  EXPECT_EQ(m.instances[0].node, 1);
  expect_near(apply(m.instances[0].world, {1, 0, 0}), apply(g, {1, 4, 3}));
  // node 2: origin -> (0, 0, 5) -> scale (0, 0, 10) -> rotate about z: same -> (1, 2, 13).
  EXPECT_EQ(m.instances[1].node, 2);
  expect_near(apply(m.instances[1].world, {0, 0, 0}), apply(g, {1, 2, 13}));
}
TEST(GltfNodes, InvalidNodeGraphs) {
  PENUMBRA_STABILITY(
      "node graphs with a cycle, a node of two parents, children or meshes out of range, a bad "
      "matrix, a zero quaternion",
      "LoadError naming the node and the reason", "-");
  GltfDoc cycle = GltfDoc::triangle();
  cycle.j["nodes"] = {{{"children", {1}}}, {{"children", {2}}, {"mesh", 0}}, {{"children", {1}}}};
  expect_error(cycle, "node 1 is a child of both node 0 and node 2");
  GltfDoc self = GltfDoc::triangle();
  self.j["nodes"] = {{{"mesh", 0}}, {{"children", {1}}}};
  expect_error(self, "recursive node graph: node 1 is its own ancestor");
  GltfDoc ring = GltfDoc::triangle();
  ring.j["nodes"] = {{{"mesh", 0}}, {{"children", {2}}}, {{"children", {3}}}, {{"children", {1}}}};
  expect_error(ring, "recursive node graph");
  GltfDoc child = GltfDoc::triangle();
  child.j["nodes"][0]["children"] = {7};
  expect_error(child, "node 0: child 7 out of range");
  GltfDoc not_root = GltfDoc::triangle();
  not_root.j["nodes"] = {{{"children", {1}}}, {{"mesh", 0}}};
  not_root.j["scenes"][0]["nodes"] = {1};
  expect_error(not_root, "scene node 1 is not a root node");
  GltfDoc mesh = GltfDoc::triangle();
  mesh.j["nodes"][0]["mesh"] = 5;
  expect_error(mesh, "mesh 5 out of range");
  GltfDoc matrix = GltfDoc::triangle();
  matrix.j["nodes"][0]["matrix"] = {1, 0, 0};
  expect_error(matrix, "node 0: matrix needs 16 numbers");
  GltfDoc quat = GltfDoc::triangle();
  quat.j["nodes"][0]["rotation"] = {0, 0, 0, 0};
  expect_error(quat, "rotation quaternion has zero length");
}
TEST(GltfNodes, NoSceneDrawsEveryRoot) {
  GltfDoc d = GltfDoc::triangle();
  d.j.erase("scene");
  d.j.erase("scenes");
  d.j["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"mesh", 0}}, {{"mesh", 0}}};
  const Model m = load(d);
  ASSERT_EQ(m.instances.size(), 3u);  // roots 0 and 2, and 1 below 0
  EXPECT_EQ(m.instances[0].node, 0);
  EXPECT_EQ(m.instances[1].node, 1);
  EXPECT_EQ(m.instances[2].node, 2);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("no scene"), std::string::npos);
  d.j["scenes"] =
      nlohmann::json::array({nlohmann::json::object()});  // a scene without nodes draws nothing
  EXPECT_TRUE(load(d).instances.empty());
}

}  // namespace
}  // namespace penumbra::assets
