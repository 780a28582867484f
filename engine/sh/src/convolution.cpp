#include "penumbra/sh/convolution.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/sh/projection.h"

namespace penumbra::sh {

template <int N>
Coeffs<N> convolve(const Coeffs<N>& f, const Zonal<N>& kernel) {
  Coeffs<N> out = f;
  for (int l = 0; l < N; ++l) {
    const float k = std::sqrt(4 * std::numbers::pi_v<float> / static_cast<float>(2 * l + 1)) * kernel[l];
    for (int m = -l; m <= l; ++m) out[index(l, m)] *= k;
  }
  return out;
}

template <int N>
Coeffs<N> irradiance_convolve(const Coeffs<N>& radiance) {
  static const Zonal<N> kernel = zh_clamped_cosine<N>();
  return convolve<N>(radiance, kernel);
}

template <int N>
std::array<float, N> hanning_window(float w) {
  std::array<float, N> out{};
  for (int l = 0; l < N; ++l) {
    out[l] = l < w ? 0.5f * (1 + std::cos(std::numbers::pi_v<float> * static_cast<float>(l) / w)) : 0.0f;
  }
  return out;
}

template <int N>
Coeffs<N> apply_window(const Coeffs<N>& f, const std::array<float, N>& window) {
  Coeffs<N> out = f;
  for (int l = 0; l < N; ++l) {
    for (int m = -l; m <= l; ++m) out[index(l, m)] *= window[l];
  }
  return out;
}

template <int N>
float min_value(const Coeffs<N>& f) {
  static const SphereQuadrature q = SphereQuadrature::gauss(4 * N, 8 * N);
  float lo = INFINITY;
  for (const glm::vec3& d : q.directions) lo = std::min(lo, evaluate<N>(f, d));
  return lo;
}

template <int N>
Coeffs<N> dering_irradiance(const Coeffs<N>& radiance, std::array<float, N>* window_out,
                            float tolerance) {
  const Coeffs<N> e = irradiance_convolve<N>(radiance);
  const float dc = e[0] * 0.28209479f;  // mean irradiance
  auto ok = [&](const Coeffs<N>& c) { return min_value<N>(c) >= -tolerance * std::fabs(dc); };
  std::array<float, N> window;
  window.fill(1.0f);
  if (!ok(e)) {
    // Bisection on the window width: wider is weaker. ok(w) is monotone for the Hanning family
    // in practice; the result is checked again below.
    float lo = 1.0f, hi = 8.0f * N;
    if (!ok(apply_window<N>(e, hanning_window<N>(hi)))) {
      for (int it = 0; it < 30; ++it) {
        const float mid = 0.5f * (lo + hi);
        if (ok(apply_window<N>(e, hanning_window<N>(mid)))) {
          lo = mid;
        } else {
          hi = mid;
        }
      }
      window = hanning_window<N>(lo);
    } else {
      window = hanning_window<N>(hi);
    }
  }
  if (window_out != nullptr) *window_out = window;
  return apply_window<N>(e, window);
}

#define PENUMBRA_CONV_INSTANTIATE(N)                                                      \
  template Coeffs<N> convolve<N>(const Coeffs<N>&, const Zonal<N>&);                     \
  template Coeffs<N> irradiance_convolve<N>(const Coeffs<N>&);                           \
  template std::array<float, N> hanning_window<N>(float);                                \
  template Coeffs<N> apply_window<N>(const Coeffs<N>&, const std::array<float, N>&);     \
  template float min_value<N>(const Coeffs<N>&);                                         \
  template Coeffs<N> dering_irradiance<N>(const Coeffs<N>&, std::array<float, N>*, float);
PENUMBRA_CONV_INSTANTIATE(2)
PENUMBRA_CONV_INSTANTIATE(3)
PENUMBRA_CONV_INSTANTIATE(4)
PENUMBRA_CONV_INSTANTIATE(5)
PENUMBRA_CONV_INSTANTIATE(6)
#undef PENUMBRA_CONV_INSTANTIATE

}  // namespace penumbra::sh
