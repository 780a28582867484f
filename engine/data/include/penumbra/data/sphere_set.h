// A sphere of a sphere set (dynamic blockers, [Giraud] sec. 4.2, [Guerrero08] sec. 4.1): plain
// data shared by the sphere file and fitter (engine/assets: sphere_file.h, sphere_fit.h) and the
// SphereSet component (components/sphere_set.h aliases it). Threading: a plain value type.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

namespace penumbra::data {

struct Sphere {
  glm::vec3 centre{0.0f};  // in the owner's local frame, metres
  float radius = 0;        // metres, >= 0 (0: no blocker)
  // Index of the bounding parent sphere in the same set, or -1 for a root ([Ren06] hierarchy).
  std::int32_t parent = -1;
};

}  // namespace penumbra::data
