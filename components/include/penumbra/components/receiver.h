// Points to shade, per entity: mesh vertices (or any sample points), with their normals, in the
// entity's local frame (the entity's Transform applies). The blocker accumulation system shades
// them into ReceiverLighting.
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::components {

struct Receiver {
  std::shared_ptr<const std::vector<glm::vec3>> points;   // local frame, metres
  std::shared_ptr<const std::vector<glm::vec3>> normals;  // one per point, unit length
};

}  // namespace penumbra::components
