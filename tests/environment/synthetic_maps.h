// Synthetic equirectangular maps for the environment tests: a flat background and discs
// ("suns") of given direction, angular radius and radiance (penumbra/sh/projection.h frame).
#pragma once

#include <cmath>
#include <cstddef>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/sh/projection.h"

namespace penumbra::test {

constexpr float kPi = 3.14159265358979f;
constexpr float kDeg = kPi / 180.0f;

inline glm::vec3 texel_direction(const data::EnvironmentMap& m, std::size_t i) {
  const auto w = static_cast<std::size_t>(m.width);
  return sh::equirect_direction((static_cast<float>(i % w) + 0.5f) / static_cast<float>(m.width),
                                (static_cast<float>(i / w) + 0.5f) / static_cast<float>(m.height));
}

// Unit direction from azimuth (from +x towards +y) and elevation, degrees.
inline glm::vec3 dir_deg(float azimuth, float elevation) {
  const float a = azimuth * kDeg, e = elevation * kDeg;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

inline float angle_deg(const glm::vec3& a, const glm::vec3& b) {
  return std::acos(
             std::fmin(1.0f, std::fmax(-1.0f, glm::dot(glm::normalize(a), glm::normalize(b))))) /
         kDeg;
}

inline data::EnvironmentMap flat_map(int w, int h, glm::vec3 rgb, std::string name = "synthetic") {
  data::EnvironmentMap m;
  m.width = w;
  m.height = h;
  m.source = std::move(name);
  m.rgb.resize(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < m.rgb.size(); i += 3) {
    m.rgb[i] = rgb.r;
    m.rgb[i + 1] = rgb.g;
    m.rgb[i + 2] = rgb.b;
  }
  return m;
}

// Sets every texel whose centre is within `radius_deg` of `dir` to `rgb`; returns their count.
inline int add_disc(data::EnvironmentMap& m, glm::vec3 dir, float radius_deg, glm::vec3 rgb) {
  const float c = std::cos(radius_deg * kDeg);
  int count = 0;
  const std::size_t n = static_cast<std::size_t>(m.width) * m.height;
  for (std::size_t i = 0; i < n; ++i) {
    if (glm::dot(texel_direction(m, i), glm::normalize(dir)) < c) continue;
    m.rgb[3 * i] = rgb.r;
    m.rgb[3 * i + 1] = rgb.g;
    m.rgb[3 * i + 2] = rgb.b;
    ++count;
  }
  return count;
}

// Luminous energy (eq. 3.1 luminance x solid angle) of the whole map, or of the texels within
// `radius_deg` of `dir` when radius_deg > 0.
inline double luminous_energy(const data::EnvironmentMap& m, glm::vec3 dir = {0, 0, 1},
                              float radius_deg = -1.0f) {
  double e = 0;
  const float c = std::cos(radius_deg * kDeg);
  const std::size_t n = static_cast<std::size_t>(m.width) * m.height;
  for (std::size_t i = 0; i < n; ++i) {
    if (radius_deg > 0 && glm::dot(texel_direction(m, i), glm::normalize(dir)) < c) continue;
    const float* p = m.rgb.data() + 3 * i;
    const double lum = 179.0 * (0.265 * p[0] + 0.670 * p[1] + 0.065 * p[2]);
    e += lum * sh::equirect_texel_solid_angle(
                   static_cast<int>(i / static_cast<std::size_t>(m.width)), m.width, m.height);
  }
  return e;
}

}  // namespace penumbra::test
