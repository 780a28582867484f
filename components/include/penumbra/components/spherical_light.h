// A local light: a sphere of uniform radiance ([Meier13] sec. 4.3, fig. 4.11).
// Seen from outside, every direction that meets the sphere carries `radiance`; a receiver at
// distance d > radius gets irradiance pi * radiance * (radius / d)^2 facing it unoccluded.
#pragma once

#include <glm/vec3.hpp>

namespace penumbra::components {

struct SphericalLight {
  glm::vec3 position{0.0f};  // world centre, metres
  float radius = 1.0f;       // metres; 0 means no light (culled)
  glm::vec3 radiance{1.0f};  // linear RGB, W / (m^2 sr)
};

}  // namespace penumbra::components
