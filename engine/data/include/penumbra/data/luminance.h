// luminance(rgb): the Rec. 709 luminance of linear RGB (ITU-R BT.709 weights), the scalar the
// reference's importance sampling and the refresh policies measure light by. Threading: a pure
// function.
#pragma once

#include <glm/vec3.hpp>

namespace penumbra::data {

inline float luminance(const glm::vec3& rgb) {
  return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z;
}

}  // namespace penumbra::data
