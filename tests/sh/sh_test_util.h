// Helpers shared by the SH tests: random inputs and brute-force references.
#pragma once

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "common/constants.h"
#include "common/random_draws.h"
#include "penumbra/sh/basis.h"
#include "penumbra/sh/projection.h"

namespace penumbra::sh::test {

inline glm::vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<float> n(0, 1);
  for (;;) {
    const glm::vec3 v = penumbra::test::draw_zyx<glm::vec3>(rng, n);
    const float len = glm::length(v);
    if (len > 1e-3f) return v / len;
  }
}

template <int N>
Coeffs<N> random_coeffs(std::mt19937& rng, float scale = 1.0f) {
  std::uniform_real_distribution<float> u(-scale, scale);
  Coeffs<N> c;
  for (float& x : c) x = u(rng);
  return c;
}

// Relative L2 distance |a - b| / max(|b|, floor).
template <int N>
float rel_l2(const Coeffs<N>& a, const Coeffs<N>& b, float floor = 1e-6f) {
  double d = 0, n = 0;
  for (int i = 0; i < N * N; ++i) {
    d += double(a[i] - b[i]) * (a[i] - b[i]);
    n += double(b[i]) * b[i];
  }
  return static_cast<float>(std::sqrt(d) / std::fmax(std::sqrt(n), floor));
}

// A fine quadrature for brute-force integrals of smooth (or mildly kinked) functions.
inline const SphereQuadrature& fine_quadrature() {
  static const SphereQuadrature q = SphereQuadrature::gauss(96, 192);
  return q;
}

}  // namespace penumbra::sh::test
