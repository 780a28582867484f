// Dynamic blockers as sets of spheres ([Giraud] sec. 4.2, [Guerrero08] sec. 4.1): a plain
// component of an entity with a Transform. The blocker accumulation system moves the spheres to
// world space each frame (penumbra/systems/blocker_accumulation/).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::components {

struct Sphere {
  glm::vec3 centre{0.0f};  // in the entity's local frame (Transform applies), metres
  float radius = 0;        // metres, >= 0 (0: no blocker)
  // Index of the bounding parent sphere in the same set, or -1 for a root ([Ren06] hierarchy).
  std::int32_t parent = -1;
};

// Shared and immutable, like MeshInstance's mesh: many entities may use one fitted set.
struct SphereSet {
  std::shared_ptr<const std::vector<Sphere>> spheres;
};

}  // namespace penumbra::components
