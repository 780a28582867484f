#include "penumbra/render/camera.h"

#include <gtest/gtest.h>

#include <glm/vec4.hpp>

namespace penumbra::render {
namespace {

glm::vec3 project(const glm::mat4& m, glm::vec3 p) {
  const glm::vec4 c = m * glm::vec4(p, 1.0f);
  return glm::vec3(c) / c.w;
}

TEST(CameraView, VulkanClipConventionsWithReversedDepth) {
  CameraView cam;
  cam.position = {0, -10, 0};
  cam.target = {0, 0, 0};
  cam.near_plane = 1.0f;
  cam.far_plane = 100.0f;
  const glm::mat4 vp = view_projection(cam, 2.0f);
  EXPECT_NEAR(project(vp, {0, 0, 0}).x, 0.0f, 1e-6f);
  EXPECT_NEAR(project(vp, {0, 0, 0}).y, 0.0f, 1e-6f);
  EXPECT_LT(project(vp, {0, 0, 1}).y, 0.0f) << "world up (+z) is up on screen: clip y < 0";
  EXPECT_GT(project(vp, {1, 0, 0}).x, 0.0f) << "+x is to the right looking along +y";
  EXPECT_NEAR(project(vp, {0, -9, 0}).z, 1.0f, 1e-5f) << "near plane at depth 1";
  EXPECT_NEAR(project(vp, {0, 90, 0}).z, 0.0f, 1e-5f) << "far plane at depth 0";
  EXPECT_GT(project(vp, {0, 0, 0}).z, project(vp, {0, 10, 0}).z) << "nearer is greater";
}

TEST(CameraView, LookingAlongUpStaysFinite) {
  CameraView cam;
  cam.position = {0, 0, 10};
  cam.target = {0, 0, 0};  // straight down, parallel to up
  const glm::mat4 v = view_matrix(cam);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_TRUE(std::isfinite(v[c][r]));
  EXPECT_NEAR(project(view_projection(cam, 1.0f), {0, 0, 0}).x, 0.0f, 1e-6f);
}

}  // namespace
}  // namespace penumbra::render
