// Convolution with zonal kernels, irradiance, and windowing (deringing).
#pragma once

#include <array>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/zh.h"

namespace penumbra::sh {

// f convolved with the zonal kernel k: band l scaled by sqrt(4 pi / (2l + 1)) k_l
// (Funk-Hecke, as in [Giraud] eq. 5).
template <int N>
Coeffs<N> convolve(const Coeffs<N>& f, const Zonal<N>& kernel);

// Irradiance from radiance L: E(n) = integral L(w) max(n.w, 0) dw. Band weights pi, 2pi/3, pi/4,
// 0, -pi/24, 0 (Ramamoorthi and Hanrahan 2001).
template <int N>
Coeffs<N> irradiance_convolve(const Coeffs<N>& radiance);

// Per-band weights of a Hanning window of width w (> 0): (1 + cos(pi l / w)) / 2 for l < w,
// 0 beyond. Larger w windows less.
template <int N>
std::array<float, N> hanning_window(float w);

template <int N>
Coeffs<N> apply_window(const Coeffs<N>& f, const std::array<float, N>& window);

// Minimum of the function over a dense set of directions (quadrature nodes of order 4N).
template <int N>
float min_value(const Coeffs<N>& f);

// Deringing for irradiance: the weakest Hanning window (largest width, by bisection) under
// which irradiance_convolve(radiance) is non-negative everywhere (min_value >= -tolerance *
// DC value). `window_out` receives the window (all ones if none was needed).
// Graceful fallback: if even the strongest window (width 1: DC only) is needed, that is used;
// a DC-only irradiance of non-negative mean radiance is non-negative.
template <int N>
Coeffs<N> dering_irradiance(const Coeffs<N>& radiance, std::array<float, N>* window_out = nullptr,
                            float tolerance = 1e-4f);

}  // namespace penumbra::sh
