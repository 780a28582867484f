#include "penumbra/systems/spherical_lights/sphere_light_tables.h"

#include <algorithm>
#include <cmath>

#include "penumbra/sh/rotation.h"

namespace penumbra::spherical_lights {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

template <int N>
AverageRadianceTable<N>::AverageRadianceTable(AverageRadianceWeight weight)
    : weight_(weight), table_(kEntries + 1) {
  constexpr int kSteps = 2048;
  for (int i = 0; i <= kEntries; ++i) {
    const double s = std::min(static_cast<double>(i) / kEntries, 0.999);
    double z[N] = {}, total = 0, p[N + 1];
    const double dx = (1.0 - s) / kSteps;
    for (int k = 0; k < kSteps; ++k) {
      const double x = s + (k + 0.5) * dx;  // cos alpha
      // [Guerrero08] eq. 17, simplified (header).
      const double v2 = std::max(1e-30, 1.0 - 2.0 * s * x + s * s);  // |v|^2, unit distance
      double f = (x - s) / std::sqrt(v2);
      if (weight == AverageRadianceWeight::kSolidAngle) f /= v2;  // header: ours
      sh::legendre(x, N, p);
      for (int l = 0; l < N; ++l) z[l] += f * std::sqrt((2 * l + 1) / (4 * kPi)) * p[l] * dx;
      total += f * dx;
    }
    for (int l = 0; l < N; ++l) table_[i][l] = static_cast<float>(z[l] / total);  // eq. 16
  }
}

template <int N>
sh::Zonal<N> AverageRadianceTable<N>::weights(float sin_angle) const {
  const float x = std::clamp(sin_angle, 0.0f, 1.0f) * kEntries;
  const int i = std::min(static_cast<int>(x), kEntries - 1);
  const float t = x - static_cast<float>(i);
  sh::Zonal<N> w;
  for (int l = 0; l < N; ++l) w[l] = table_[i][l] + t * (table_[i + 1][l] - table_[i][l]);
  return w;
}

template <int N>
glm::vec3 AverageRadianceTable<N>::average_radiance(const sh::CoeffsRgb<N>& radiance,
                                                    float sin_angle,
                                                    const glm::vec3& to_receiver) const {
  const sh::Coeffs<N> w = sh::rotate_zh<N>(weights(sin_angle), to_receiver);  // eq. 18
  return {sh::dot<N>(w, radiance[0]), sh::dot<N>(w, radiance[1]), sh::dot<N>(w, radiance[2])};
}

float cap_cosine_integral(float sin_angle, float cos_beta) {
  const float s2 = std::min(sin_angle * sin_angle, 1.0f - 1e-6f);
  if (!(s2 > 0)) return 0;
  const float cb = std::clamp(cos_beta, -1.0f, 1.0f);
  if (cb * cb > s2) return cb > 0 ? static_cast<float>(kPi) * s2 * cb : 0.0f;
  // Partly below the horizon (Lagarde and de Rousiers 2014, eq. 20, after Snyder).
  const float sb = std::sqrt(std::max(0.0f, 1.0f - cb * cb));
  const float x = std::sqrt(1.0f / s2 - 1.0f);
  const float y = std::clamp(-x * cb / sb, -1.0f, 1.0f);
  const float t = sb * std::sqrt(std::max(0.0f, 1.0f - y * y));
  return std::max(0.0f, (cb * std::acos(y) - x * t) * s2 + std::atan2(t, x));
}

namespace {
// atan per lane for x >= 0 (Cephes atanf: two range reductions, then a degree-9 odd polynomial;
// Cephes documents a peak relative error of 1.9e-7). +inf gives pi / 2.
sh::Lanes lane_atan(sh::Lanes x) {
  const float pi = static_cast<float>(kPi);
  const sh::LaneMask big = x > 2.414213562373095f, mid = ~big & (x > 0.4142135623730950f);
  const sh::Lanes one = sh::splat(1.0f);
  const sh::Lanes reduced = sh::select(big, -one / x, sh::select(mid, (x - one) / (x + one), x));
  const sh::Lanes base =
      sh::select(big, sh::splat(0.5f * pi), sh::select(mid, sh::splat(0.25f * pi), sh::Lanes{}));
  const sh::Lanes z = reduced * reduced;
  const sh::Lanes poly =
      ((sh::splat(8.05374449538e-2f) * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z -
      3.33329491539e-1f;
  return base + (poly * z * reduced + reduced);
}
}  // namespace

sh::Lanes cap_cosine_integral_lanes(sh::Lanes sin_angle, sh::Lanes cos_beta) {
  // cap_cosine_integral per lane; acos(y) = 2 atan(sqrt((1 - y) / (1 + y))), atan2(t, x) =
  // atan(t / x) as t >= 0 and x > 0.
  using sh::Lanes;
  const Lanes one = sh::splat(1.0f), zero{};
  const Lanes s2 = sh::lane_min(sin_angle * sin_angle, sh::splat(1.0f - 1e-6f));
  const Lanes cb = sh::lane_max(sh::lane_min(cos_beta, one), -one);
  const Lanes above = sh::select(cb > 0, static_cast<float>(kPi) * s2 * cb, zero);
  const sh::LaneMask clipped = ~(cb * cb > s2) & (s2 > 0);
  if (sh::lane_bits(clipped) == 0) return sh::select(s2 > 0, above, zero);
  const Lanes sb = sh::lane_sqrt(one - cb * cb);
  const Lanes x = sh::lane_sqrt(one / sh::select(s2 > 0, s2, one) - one);
  const Lanes y = sh::lane_max(sh::lane_min(-x * cb / sh::select(sb > 0, sb, one), one), -one);
  const Lanes t = sb * sh::lane_sqrt(one - y * y);
  const Lanes acos_y = 2.0f * lane_atan(sh::lane_sqrt((one - y) / (one + y)));
  const Lanes part = (cb * acos_y - x * t) * s2 + lane_atan(t / sh::select(x > 0, x, one));
  return sh::select(clipped, sh::lane_max(part, zero), sh::select(s2 > 0, above, zero));
}

template class AverageRadianceTable<3>;
template class AverageRadianceTable<4>;
template class AverageRadianceTable<5>;

}  // namespace penumbra::spherical_lights
