// finite(v): whether every component of a glm vector or matrix is finite (no NaN, no infinity),
// the check loaders and systems make of their inputs before using them. Threading: pure
// functions.
#pragma once

#include <cmath>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace penumbra::data {

template <glm::length_t N, class T, glm::qualifier Q>
bool finite(const glm::vec<N, T, Q>& v) {
  for (glm::length_t i = 0; i < N; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

template <glm::length_t C, glm::length_t R, class T, glm::qualifier Q>
bool finite(const glm::mat<C, R, T, Q>& m) {
  for (glm::length_t c = 0; c < C; ++c) {
    if (!finite(m[c])) return false;
  }
  return true;
}

}  // namespace penumbra::data
