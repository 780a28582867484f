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

// Diffuse albedo and Phong exponent of a receiver's surface ([Giraud] sec. 5).
struct Material {
  glm::vec3 albedo{0.8f};
  float phong_exponent = 0;  // 0: diffuse only
};

}  // namespace penumbra::components
