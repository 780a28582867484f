#include "penumbra/render/camera.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace penumbra::render {

glm::mat4 view_matrix(const CameraView& camera) {
  glm::vec3 up = camera.up;
  const glm::vec3 forward = camera.target - camera.position;
  // A view straight along `up` has no defined roll: pick another up rather than produce NaNs.
  if (glm::length(glm::cross(forward, up)) < 1e-6f * glm::length(forward))
    up = std::fabs(forward.z) > std::fabs(forward.y) ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
  return glm::lookAtRH(camera.position, camera.target, up);
}

glm::mat4 projection_matrix(const CameraView& camera, float aspect) {
  // perspectiveRH_ZO maps near -> 0, far -> 1; passing (far, near) reverses depth.
  glm::mat4 p =
      glm::perspectiveRH_ZO(camera.vertical_fov, aspect, camera.far_plane, camera.near_plane);
  p[1][1] = -p[1][1];  // Vulkan clip space: y down
  return p;
}

}  // namespace penumbra::render
