// 26-direction sampling, contrast and irradiance vector (probe_sampling.h), [Sukys14] 3.1.3.
#include "penumbra/systems/probe_bake/probe_sampling.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "penumbra/sh/basis.h"

namespace penumbra::probe_bake {
namespace {

std::array<glm::vec3, kSampleDirections> make_directions() {
  std::array<glm::vec3, kSampleDirections> d{};
  int k = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (float s : {1.0f, -1.0f}) {
      glm::vec3 v(0.0f);
      v[axis] = s;
      d[k++] = v;
    }
  for (int a = 0; a < 3; ++a)  // edges: two axes
    for (int b = a + 1; b < 3; ++b)
      for (float sa : {1.0f, -1.0f})
        for (float sb : {1.0f, -1.0f}) {
          glm::vec3 v(0.0f);
          v[a] = sa;
          v[b] = sb;
          d[k++] = glm::normalize(v);
        }
  for (float sx : {1.0f, -1.0f})  // corners
    for (float sy : {1.0f, -1.0f})
      for (float sz : {1.0f, -1.0f}) d[k++] = glm::normalize(glm::vec3(sx, sy, sz));
  return d;
}

template <int N>
DirectionSamples sample(std::span<const float> sh) {
  constexpr int kC = N * N;
  DirectionSamples out{};
  const auto& dirs = sample_directions();
  const float w[3] = {0.2126f, 0.7152f, 0.0722f};
  for (int k = 0; k < kSampleDirections; ++k) {
    const auto y = sh::eval_basis<N>(dirs[k]);
    double lum = 0;
    for (int c = 0; c < 3; ++c) {
      double e = 0;
      for (int i = 0; i < kC; ++i) e += double(sh[c * kC + i]) * y[i];
      lum += w[c] * std::max(0.0, e);
    }
    out[k] = static_cast<float>(lum);
  }
  return out;
}

}  // namespace

const std::array<glm::vec3, kSampleDirections>& sample_directions() {
  static const std::array<glm::vec3, kSampleDirections> d = make_directions();
  return d;
}

DirectionSamples sample_irradiance(std::span<const float> sh, int bands) {
  switch (bands) {
    case 2:
      return sample<2>(sh);
    case 3:
      return sample<3>(sh);
    default:
      return sample<4>(sh);
  }
}

float probe_contrast(const DirectionSamples& a, const DirectionSamples& b, float floor) {
  float c = 0;
  for (int k = 0; k < kSampleDirections; ++k) {
    const float den = a[k] + b[k] + floor;
    if (den > 0) c = std::max(c, std::abs(a[k] - b[k]) / den);
  }
  return c;
}

glm::vec3 irradiance_vector(const DirectionSamples& s) {
  glm::dvec3 v(0.0);
  double sum = 0;
  const auto& dirs = sample_directions();
  for (int k = 0; k < kSampleDirections; ++k) {
    v += glm::dvec3(dirs[k]) * double(s[k]);
    sum += s[k];
  }
  if (!(sum > 0)) return glm::vec3(0.0f);
  return glm::vec3(v / sum);
}

}  // namespace penumbra::probe_bake
