#include "penumbra/systems/spherical_lights/reflector_samples.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/stability.h"
#include "test_meshes.h"

namespace penumbra::spherical_lights {
namespace {

TEST(GeodesicDirections, FrequencyThreeGivesTheDocumentsNinetyTwoUnitDirections) {
  for (int f : {1, 2, 3, 4}) {
    const std::vector<glm::vec3> d = geodesic_directions(f);
    EXPECT_EQ(d.size(), static_cast<std::size_t>(10 * f * f + 2)) << f;
    glm::vec3 sum(0.0f);
    float closest = 2;
    for (std::size_t i = 0; i < d.size(); ++i) {
      EXPECT_NEAR(glm::length(d[i]), 1.0f, 1e-6f);
      sum += d[i];
      for (std::size_t j = 0; j < i; ++j) closest = std::min(closest, glm::length(d[i] - d[j]));
    }
    EXPECT_NEAR(glm::length(sum), 0.0f, 1e-4f);        // symmetric
    EXPECT_GT(closest, 0.5f / static_cast<float>(f));  // no duplicates
  }
  EXPECT_THROW(geodesic_directions(0), std::invalid_argument);
}

TEST(SampleReflector, OneSphereAroundABoxFindsEveryDirectionOnTheSurfaceFacingOut) {
  const data::MeshData box =
      test::box_mesh(glm::vec3(-1), glm::vec3(1), glm::vec3(0.8f, 0.2f, 0.1f));
  const std::vector<data::Sphere> spheres = {{glm::vec3(0), std::sqrt(3.0f) + 1e-3f, -1}};
  const ReflectorSamples s = sample_reflector(box, spheres);
  ASSERT_EQ(s.lights.size(), 1u);
  const SphereSamples& sl = s.lights[0];
  EXPECT_EQ(sl.count(), 92);
  for (int j = 0; j < 92; ++j) {
    const glm::vec3 p = sl.positions[j];
    const float linf = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    EXPECT_NEAR(linf, 1.0f, 1e-5f) << j;                                     // on the box
    EXPECT_GT(glm::dot(sl.normals[j], s.directions[j]), 0.0f) << j;          // facing out
    EXPECT_NEAR(glm::dot(glm::normalize(p), s.directions[j]), 1.0f, 1e-5f);  // along its ray
    EXPECT_EQ(sl.albedo[j], glm::vec3(0.8f, 0.2f, 0.1f));
  }
}

TEST(SampleReflector, TwoSpheresSplitTheSurfaceAndDropDirectionsTheOtherCovers) {
  // A 4 x 1 x 1 bar, two spheres over its halves: they intersect in the middle.
  const data::MeshData bar = test::box_mesh(glm::vec3(-2, -0.5f, -0.5f), glm::vec3(2, 0.5f, 0.5f));
  const float r = std::sqrt(1.0f + 0.5f) + 1e-3f;
  const std::vector<data::Sphere> spheres = {{glm::vec3(-1, 0, 0), r, -1},
                                             {glm::vec3(1, 0, 0), r, -1}};
  const ReflectorSamples s = sample_reflector(bar, spheres);
  for (int k = 0; k < 2; ++k) {
    const SphereSamples& sl = s.lights[k];
    const float side = k == 0 ? -1.0f : 1.0f;
    int towards_other = 0;
    for (int j = 0; j < 92; ++j) {
      const glm::vec3 on_sphere = sl.centre + sl.radius * s.directions[j];
      const bool covered = glm::length(on_sphere - spheres[1 - k].centre) < spheres[1 - k].radius;
      if (covered) {
        EXPECT_EQ(sl.valid[j], 0) << k << " " << j;  // [Guerrero08] sec. 6.2
        ++towards_other;
      }
      if (sl.valid[j]) {
        EXPECT_GE(sl.positions[j].x * side, -1e-5f) << k << " " << j;  // own half
      }
    }
    EXPECT_GT(towards_other, 5);
    EXPECT_GT(sl.count(), 40);
  }
}

TEST(SampleReflector, ACentreOutsideTheObjectUsesTheOppositeRaysFrontSide) {
  PENUMBRA_STABILITY("a sphere centre outside its object (a thin slab below it)",
                     "rays meeting nothing take the opposite rays' front side: the slab's top face",
                     "-");
  // A thin slab below a sphere whose centre is above it: rays upwards meet nothing, so the
  // opposite (downward) rays give the slab's top face (case 3).
  const data::MeshData slab = test::box_mesh(glm::vec3(-1, -1, -0.1f), glm::vec3(1, 1, 0));
  const std::vector<data::Sphere> spheres = {{glm::vec3(0, 0, 0.2f), 1.5f, -1}};
  const ReflectorSamples s = sample_reflector(slab, spheres);
  int top = 0;
  for (int j = 0; j < 92; ++j) {
    if (!s.lights[0].valid[j] || s.directions[j].z <= 0.3f) continue;
    EXPECT_NEAR(s.lights[0].positions[j].z, 0.0f, 1e-5f) << j;
    EXPECT_GT(s.lights[0].normals[j].z, 0.99f) << j;
    ++top;
  }
  EXPECT_GT(top, 5);
}

TEST(SampleReflector, ARayThroughASharedEdgeFindsItsPoint) {
  // A quad facing away from the centre across every geodesic direction's path, each split along
  // a diagonal through the point the ray meets: float rounding must not let the ray slip
  // between the two triangles (it did on meshes whose edges line up with geodesic directions).
  const std::vector<glm::vec3> dirs = geodesic_directions(3);
  int hit = 0;
  for (const glm::vec3& d : dirs) {
    const glm::vec3 t = std::abs(d.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 u = glm::normalize(glm::cross(d, t)), v = glm::cross(d, u);
    data::MeshData quad;
    quad.name = "quad";
    const glm::vec3 c = 2.0f * d;
    quad.positions = {c - u - v, c + u - v, c + u + v, c - u + v};
    quad.indices = {0, 1, 2, 0, 2, 3};  // the diagonal 0-2 passes through c; normal +d
    const ReflectorSamples s =
        sample_reflector(quad, std::vector<data::Sphere>{{glm::vec3(0), 3.0f, -1}});
    const auto j = static_cast<std::size_t>(&d - dirs.data());
    hit += s.lights[0].valid[j];
    if (s.lights[0].valid[j]) {
      EXPECT_NEAR(glm::length(s.lights[0].positions[j] - c), 0.0f, 1e-5f);
    }
  }
  EXPECT_EQ(hit, 92);
}

TEST(SampleReflector, BadInputNamesTheMeshAndTheReason) {
  PENUMBRA_STABILITY(
      "no spheres, radius 0, NaN centre, a mesh of nothing; a sphere whose segment is empty",
      "std::invalid_argument naming the mesh; the empty segment is valid and emits nothing", "-");
  data::MeshData box = test::box_mesh(glm::vec3(-1), glm::vec3(1));
  const std::vector<data::Sphere> ok = {{glm::vec3(0), 2.0f, -1}};
  data::MeshData empty;
  empty.name = "nothing";
  try {
    sample_reflector(empty, ok);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nothing"), std::string::npos) << e.what();
  }
  const std::vector<data::Sphere> zero = {{glm::vec3(0), 0.0f, -1}};
  EXPECT_THROW(sample_reflector(box, zero), std::invalid_argument);
  const std::vector<data::Sphere> nan = {{glm::vec3(NAN), 1.0f, -1}};
  EXPECT_THROW(sample_reflector(box, nan), std::invalid_argument);
  box.indices.push_back(999), box.indices.push_back(0), box.indices.push_back(1);
  EXPECT_THROW(sample_reflector(box, ok), std::invalid_argument);
  // A sphere whose segment is empty (eq. 2 gives the whole surface to the other) is valid and
  // emits nothing.
  const data::MeshData far = test::box_mesh(glm::vec3(10), glm::vec3(11));
  const ReflectorSamples s = sample_reflector(
      far, std::vector<data::Sphere>{{glm::vec3(10.5f), 1.0f, -1}, {glm::vec3(0), 1.0f, -1}});
  EXPECT_EQ(s.lights[0].count(), 92);
  EXPECT_EQ(s.lights[1].count(), 0);
}

}  // namespace
}  // namespace penumbra::spherical_lights
