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
  // Appended, not "literal" + string&&: GCC 12 warns falsely there (-Wrestrict, bug 105329).
  std::string s = "(";
  s += std::to_string(v.x);
  s += ", ";
  s += std::to_string(v.y);
  s += ", ";
  s += std::to_string(v.z);
  s += ")";
  return s;
}

}  // namespace penumbra::blocker_accumulation::detail
