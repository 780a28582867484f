// Zonal harmonics (ZH): coefficients z_l (l < N) of functions symmetric about +z,
// f(theta) = sum_l z_l y_l^0(theta), and the analytic profiles the lighting systems use.
// Rotate them to any direction with rotate_zh (rotation.h).
#pragma once

#include <array>

#include "penumbra/sh/basis.h"

namespace penumbra::sh {

template <int N>
using Zonal = std::array<float, N>;

// Legendre polynomials P_0..P_{n-1} at x (standard normalisation, P_l(1) = 1).
void legendre(double x, int n, double* out);

// max(cos theta, 0). Convolving with it gives irradiance (irradiance_convolve, convolution.h).
template <int N>
Zonal<N> zh_clamped_cosine();

// Indicator of the spherical cap of half-angle `half_angle` (radians) around +z:
// z_0 = 2 pi N_0 (1 - cos), z_l = 2 pi N_l (P_{l-1}(cos) - P_{l+1}(cos)) / (2l + 1), with
// N_l = sqrt((2l+1)/4pi) ([Meier13] appendix A.1, eq. 4.27; the document's
// k = 3 line prints (-1 + 5 cos)^2 where the integral gives (-1 + 5 cos^2)).
template <int N>
Zonal<N> zh_cap(float half_angle);

// Visibility of a sphere blocker seen from a receiver: 1 outside the cone it subtends,
// 0 inside. sin(half angle) = radius / distance ([Giraud] eq. 24-25).
// A receiver inside the blocker (radius >= distance) sees nothing: all-zero coefficients.
template <int N>
Zonal<N> zh_sphere_visibility(float radius, float distance);

// Log-visibility of the same blocker: log(eps) inside the cone, 0 outside ([Giraud] eq. 26).
// Inside the blocker: log(eps) everywhere.
template <int N>
Zonal<N> zh_sphere_log_visibility(float radius, float distance, float log_eps);

// Normalised Legendre polynomials (NLP) hat P_l(z) = sqrt((2l+1)/2) P_l(z), orthonormal on
// [-1, 1] ([Giraud] eq. 12-14).
template <int N>
std::array<float, N> nlp_basis(float z);

// NLP projection of a log-visibility slice with horizon angle sigma (elevation of the
// horizon, radians; negative below the horizontal plane): log(eps) for polar angle
// theta > pi/2 - sigma, 0 above ([Giraud] eq. 15, whose 4-term closed form is eq. 16).
template <int N>
std::array<float, N> nlp_log_slice(float sigma, float log_eps);

// SH coefficients of a zonal function from its ZH coefficients (the m = 0 entries).
template <int N>
Coeffs<N> zonal_to_sh(const Zonal<N>& z) {
  Coeffs<N> out{};
  for (int l = 0; l < N; ++l) out[index(l, 0)] = z[l];
  return out;
}

}  // namespace penumbra::sh
