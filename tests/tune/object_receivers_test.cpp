// What the blocker and spherical-light tuners share (game/tune/object_receivers.h): the ground
// grid under each object, its fitted spheres in world space, the reference scene of the meshes.
#include "tune/object_receivers.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <filesystem>

namespace penumbra::tune {
namespace {

TEST(ObjectReceivers, GridSpheresAndSceneFollowTheObjects) {
  const TuneScene s =
      load_tune_scene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "scenes" / "tune_ridge.json",
                      PENUMBRA_SHARED_DATA);
  ASSERT_FALSE(s.objects.empty());
  const std::vector<glm::vec3> grid = ground_receivers(s);
  ASSERT_EQ(grid.size(), 144 * s.objects.size());
  for (std::size_t k = 0; k < s.objects.size(); ++k) {
    glm::vec3 mean(0.0f);
    for (std::size_t i = 0; i < 144; ++i) {
      const glm::vec3& p = grid[144 * k + i];
      mean += p / 144.0f;
      EXPECT_LE(glm::length(glm::vec2(p - s.objects[k].ground)),
                1.25f * s.objects[k].radius * 1.4143f);
    }
    EXPECT_NEAR(glm::length(mean - s.objects[k].ground), 0.0f, 1e-3f * s.objects[k].radius);
  }
  const TuneObject& o = s.objects.front();
  const std::vector<data::Sphere> spheres = fit_world_spheres(o, 8, 1);
  ASSERT_EQ(spheres.size(), 8u);
  for (const data::Sphere& sp : spheres) {  // in world space, around the object
    EXPECT_GT(sp.radius, 0.0f);
    EXPECT_LT(glm::length(glm::vec2(sp.centre - o.ground)), 2.0f * o.radius);
  }
  const reference::SceneDesc d = object_scene(s);
  ASSERT_EQ(d.meshes.size(), s.objects.size());
  EXPECT_EQ(d.meshes.front().albedo, o.albedo);
  ASSERT_TRUE(d.environment.has_value());
}

}  // namespace
}  // namespace penumbra::tune
