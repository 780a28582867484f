// Debug shapes: what the renderer's debug pass draws (unlit, depth-tested), gathered by the
// render extract like any other renderable: wire spheres per entity (e.g. blockers while their
// system is developed, a light's extent), and lists of segments or points per entity, replaced
// by their writer each frame (e.g. the horizon wedges under the cursor, particles). World
// space, metres, linear HDR RGB.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::components {

struct DebugSphere {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 color{1.0f};
};

struct DebugLine {
  glm::vec3 a{0.0f}, b{0.0f};
  glm::vec3 color{1.0f};
};
struct DebugLines {
  std::vector<DebugLine> lines;
};

struct DebugPoint {
  glm::vec3 position{0.0f};
  glm::vec3 color{1.0f};
};
struct DebugPoints {
  std::vector<DebugPoint> points;
};

}  // namespace penumbra::components
