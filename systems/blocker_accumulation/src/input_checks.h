// Input checks shared by the blocker library's sources (not installed): finiteness and how a
// rejected vector is named in an error message.
#pragma once

#include <cmath>
#include <string>

#include <glm/vec3.hpp>

namespace penumbra::blocker_accumulation::detail {

inline bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline std::string str(const glm::vec3& v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

}  // namespace penumbra::blocker_accumulation::detail
