// Resource: the camera the game views the world through (the render extract copies it into the
// render packet). Metres and radians, z up.
#pragma once

#include <glm/vec3.hpp>

namespace penumbra::components {

struct Camera {
  glm::vec3 position{0.0f, -10.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};
  float vertical_fov = 1.0f;
  float near_plane = 0.1f;
  float far_plane = 2000.0f;
};

}  // namespace penumbra::components
