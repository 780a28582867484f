#include "penumbra/systems/probe_cloud/probe_cloud_validation.h"

#include <random>

#include <gtest/gtest.h>

#include "common/stability.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"

namespace penumbra::probe_cloud {
namespace {

data::ProbeCloud sample_cloud() {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 4.0f);
  std::vector<glm::vec3> p(200);
  for (glm::vec3& q : p) q = {u(rng), u(rng), u(rng)};
  return build_probe_cloud(p, {});
}

bool mentions(const ProbeCloudValidation& v, const std::string& what) {
  for (const std::string& e : v.errors) {
    if (e.find(what) != std::string::npos) return true;
  }
  return false;
}

TEST(ProbeCloudValidation, AcceptsABuiltCloud) {
  const ProbeCloudValidation v = validate_probe_cloud(sample_cloud());
  EXPECT_TRUE(v.ok()) << (v.errors.empty() ? "" : v.errors[0]);
}

TEST(ProbeCloudValidation, FlippedTetrahedron) {
  data::ProbeCloud cloud = sample_cloud();
  std::swap(cloud.cells[5].vertices[0], cloud.cells[5].vertices[1]);
  std::swap(cloud.cells[5].neighbours[0], cloud.cells[5].neighbours[1]);
  cloud.transforms[5] = probe_cell_transform(cloud, 5);
  const ProbeCloudValidation v = validate_probe_cloud(cloud);
  EXPECT_TRUE(mentions(v, "cell 5: tetrahedron not positively oriented"));
}

TEST(ProbeCloudValidation, BrokenLinkAndBadTransform) {
  PENUMBRA_STABILITY("a cloud with a broken neighbour link or a bad cell transform",
                     "validation errors naming the cell", "-");
  data::ProbeCloud cloud = sample_cloud();
  cloud.cells[3].neighbours[2] = (cloud.cells[3].neighbours[2] + 1) % int(cloud.inner_count);
  cloud.transforms[7][3].x += 1.0f;
  const ProbeCloudValidation v = validate_probe_cloud(cloud);
  EXPECT_TRUE(mentions(v, "cell 3: neighbour")) << v.errors[0];
  EXPECT_TRUE(mentions(v, "cell 7: transform"));
}

TEST(ProbeCloudValidation, NotDelaunay) {
  // Two tetrahedra sharing a face where a flip is needed: the apex of one lies inside the other's
  // circumsphere. Build by hand: the face (0, 1, 2), apexes 3 and 4.
  data::ProbeCloud cloud;
  cloud.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2f, 0.2f, 0.1f}, {0.2f, 0.2f, -0.1f}};
  cloud.sh.assign(5 * 27, 0.0f);
  cloud.hull_normals.assign(5, glm::vec3(0.0f));
  cloud.cells.resize(2);
  cloud.cells[0] = {{0, 1, 2, 3}, {0, 0, 1, 0}};
  cloud.cells[1] = {{1, 0, 2, 4}, {0, 0, 0, 1}};
  cloud.cells[0].neighbours = {0, 0, 0, 1};
  cloud.cells[1].neighbours = {1, 1, 1, 0};
  cloud.inner_count = 2;
  cloud.transforms = {probe_cell_transform(cloud, 0), probe_cell_transform(cloud, 1)};
  const ProbeCloudValidation v = validate_probe_cloud(cloud);
  EXPECT_TRUE(mentions(v, "not Delaunay"));
}

TEST(ProbeCloudValidation, SizesAndCap) {
  data::ProbeCloud cloud = sample_cloud();
  cloud.sh.pop_back();
  EXPECT_TRUE(mentions(validate_probe_cloud(cloud), "sh has"));
  cloud = sample_cloud();
  for (auto& t : cloud.transforms) t[3].x += 100.0f;  // every cell wrong
  const ProbeCloudValidation v = validate_probe_cloud(cloud);
  EXPECT_EQ(v.errors.size(), 21u);
  EXPECT_TRUE(mentions(v, "more"));
}

}  // namespace
}  // namespace penumbra::probe_cloud
