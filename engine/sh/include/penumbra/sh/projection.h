// Projection onto SH ([Giraud] eq. 3): of a function by spherical quadrature,
// and of an equirectangular environment map with per-texel solid-angle weights.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"

namespace penumbra::sh {

// Product quadrature on the sphere: Gauss-Legendre nodes in z = cos(theta) times uniformly
// spaced azimuths. Exact for polynomials of degree < min(2 * n_z, n_phi) restricted to the
// sphere, so n_z = N and n_phi = 2N integrate products of two N-band functions exactly.
struct SphereQuadrature {
  std::vector<glm::vec3> directions;
  std::vector<float> weights;  // sum to 4 pi

  static SphereQuadrature gauss(int n_z, int n_phi);
};

// f_i = integral f(w) y_i(w) dw, by `q`. F: float(const glm::vec3& unit_dir).
template <int N, class F>
Coeffs<N> project(F&& f, const SphereQuadrature& q) {
  Coeffs<N> out{};
  float y[N * N];
  for (std::size_t d = 0; d < q.directions.size(); ++d) {
    const float v = f(q.directions[d]) * q.weights[d];
    eval_basis<N>(q.directions[d], y);
    for (int i = 0; i < N * N; ++i) out[i] += v * y[i];
  }
  return out;
}

// --- Equirectangular maps ---------------------------------------------------------------------
// Texel (x, y) of a width x height map covers u = (x + 0.5) / width, v = (y + 0.5) / height.
// u is the azimuth phi = 2 pi u, measured from +x towards +y; v is the polar angle
// theta = pi v from +z: row 0 is the zenith (the sky of an HDR panorama), the last row the nadir.

glm::vec3 equirect_direction(float u, float v);
glm::vec2 equirect_uv(const glm::vec3& dir);
// Solid angle of one texel in row y: (2 pi / width) * (cos theta_top - cos theta_bottom).
float equirect_texel_solid_angle(int y, int width, int height);

// Projects an RGB float map (row-major, 3 floats per texel, row 0 = zenith) with exact
// per-texel solid-angle weights. Throws std::invalid_argument on a non-positive size.
template <int N>
CoeffsRgb<N> project_equirect(const float* rgb, int width, int height);

}  // namespace penumbra::sh
