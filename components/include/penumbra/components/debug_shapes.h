// Debug shapes: entities drawn by the renderer's debug pass (wire spheres, e.g. blockers while
// their system is developed). Metres, linear RGB.
#pragma once

#include <glm/vec3.hpp>

namespace penumbra::components {

struct DebugSphere {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 color{1.0f};
};

}  // namespace penumbra::components
