// Surface sample points of an object's spherical lights ([Guerrero08] sec. 4.2): plain data made
// offline by systems/spherical_lights (reflector_samples.h: sample_reflector) and shared by the
// Reflector component. Threading: a plain value type.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::data {

// One spherical light's points, one slot per direction (`valid` 0: no point in that direction).
struct SphereSamples {
  glm::vec3 centre{0.0f};  // local frame of the object, metres
  float radius = 0;
  std::vector<glm::vec3> positions;  // local frame
  std::vector<glm::vec3> normals;    // unit, outward
  std::vector<glm::vec3> albedo;     // linear RGB in [0, 1]; 0 where no point
  std::vector<std::uint8_t> valid;
  int count() const {  // valid points
    return static_cast<int>(std::count(valid.begin(), valid.end(), std::uint8_t{1}));
  }
};

// An object's spherical lights: its sphere set with their sample points, in its local frame.
struct ReflectorSamples {
  std::vector<glm::vec3> directions;  // the geodesic directions, shared by every light
  std::vector<SphereSamples> lights;  // one per sphere, in the set's order
};

}  // namespace penumbra::data
