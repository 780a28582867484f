#include "penumbra/sh/zh.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace penumbra::sh {
namespace {
double norm(int l) { return std::sqrt((2 * l + 1) / (4 * std::numbers::pi)); }
}  // namespace

void legendre(double x, int n, double* out) {
  if (n > 0) out[0] = 1;
  if (n > 1) out[1] = x;
  for (int l = 2; l < n; ++l) out[l] = ((2 * l - 1) * x * out[l - 1] - (l - 1) * out[l - 2]) / l;
}

template <int N>
Zonal<N> zh_clamped_cosine() {
  // z_l = 2 pi N_l integral_0^1 x P_l(x) dx, by 16-point Gauss-Legendre on [0, 1] (exact for
  // the polynomial integrand, degree <= N).
  static constexpr double xs[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                                   0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                                   0.9445750230732326, 0.9894009349916499};
  static constexpr double ws[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                                   0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                                   0.0622535239386479, 0.0271524594117541};
  Zonal<N> z{};
  for (int k = 0; k < 16; ++k) {
    const double t = k < 8 ? xs[k] : -xs[k - 8];
    const double w = k < 8 ? ws[k] : ws[k - 8];
    const double x = 0.5 * (t + 1);  // [-1, 1] -> [0, 1]
    double p[N];
    legendre(x, N, p);
    for (int l = 0; l < N; ++l) z[l] += static_cast<float>(0.5 * w * x * p[l] * 2 * std::numbers::pi * norm(l));
  }
  return z;
}

template <int N>
Zonal<N> zh_cap(float half_angle) {
  const double t = std::cos(std::clamp<double>(half_angle, 0.0, std::numbers::pi));
  double p[N + 1];
  legendre(t, N + 1, p);
  Zonal<N> z{};
  z[0] = static_cast<float>(2 * std::numbers::pi * norm(0) * (1 - t));
  for (int l = 1; l < N; ++l) {
    z[l] = static_cast<float>(2 * std::numbers::pi * norm(l) * (p[l - 1] - p[l + 1]) / (2 * l + 1));
  }
  return z;
}

template <int N>
Zonal<N> zh_sphere_visibility(float radius, float distance) {
  Zonal<N> z{};
  if (!(radius < distance)) return z;  // inside (or touching): fully blocked
  const Zonal<N> cap = zh_cap<N>(std::asin(radius / distance));
  for (int l = 0; l < N; ++l) z[l] = -cap[l];
  z[0] += static_cast<float>(std::sqrt(4 * std::numbers::pi));  // 1 - cap
  return z;
}

template <int N>
Zonal<N> zh_sphere_log_visibility(float radius, float distance, float log_eps) {
  Zonal<N> z{};
  if (!(radius < distance)) {
    z[0] = static_cast<float>(log_eps * std::sqrt(4 * std::numbers::pi));
    return z;
  }
  const Zonal<N> cap = zh_cap<N>(std::asin(radius / distance));
  for (int l = 0; l < N; ++l) z[l] = log_eps * cap[l];
  return z;
}

template <int N>
std::array<float, N> nlp_basis(float z) {
  double p[N];
  legendre(z, N, p);
  std::array<float, N> out{};
  for (int l = 0; l < N; ++l) out[l] = static_cast<float>(std::sqrt((2 * l + 1) / 2.0) * p[l]);
  return out;
}

template <int N>
std::array<float, N> nlp_log_slice(float sigma, float log_eps) {
  // Occluded for z = cos theta in [-1, sin sigma]:
  // integral_{-1}^{t} P_l = (P_{l+1}(t) - P_{l-1}(t)) / (2l + 1), and t + 1 for l = 0.
  const double t = std::sin(std::clamp<double>(sigma, -std::numbers::pi / 2, std::numbers::pi / 2));
  double p[N + 1];
  legendre(t, N + 1, p);
  std::array<float, N> out{};
  for (int l = 0; l < N; ++l) {
    const double integral = l == 0 ? t + 1 : (p[l + 1] - p[l - 1]) / (2 * l + 1);
    out[l] = static_cast<float>(log_eps * std::sqrt((2 * l + 1) / 2.0) * integral);
  }
  return out;
}

#define PENUMBRA_ZH_INSTANTIATE(N)                                             \
  template Zonal<N> zh_clamped_cosine<N>();                                   \
  template Zonal<N> zh_cap<N>(float);                                         \
  template Zonal<N> zh_sphere_visibility<N>(float, float);                    \
  template Zonal<N> zh_sphere_log_visibility<N>(float, float, float);         \
  template std::array<float, N> nlp_basis<N>(float);                          \
  template std::array<float, N> nlp_log_slice<N>(float, float);
PENUMBRA_ZH_INSTANTIATE(2)
PENUMBRA_ZH_INSTANTIATE(3)
PENUMBRA_ZH_INSTANTIATE(4)
PENUMBRA_ZH_INSTANTIATE(5)
PENUMBRA_ZH_INSTANTIATE(6)
#undef PENUMBRA_ZH_INSTANTIATE

}  // namespace penumbra::sh
