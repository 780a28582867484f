// Internal: the Rec. 709 luminance of linear RGB, the measure of change of the refresh policies
// (environment_refresh.cpp, light_refresh.cpp).
#pragma once

#include <glm/vec3.hpp>

namespace penumbra::terrain_shadow::detail {

inline float luminance(const glm::vec3& c) {
  return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

}  // namespace penumbra::terrain_shadow::detail
