#include "penumbra/sh/exp_log.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "band0.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/zh.h"

namespace penumbra::sh {
namespace {
using detail::kY0;  // y_0 = 1 / sqrt(4 pi)

template <int N>
const SphereQuadrature& quadrature() {
  // Degree-2N+ accurate; exp and log are not polynomials, so oversample generously.
  static const SphereQuadrature q = SphereQuadrature::gauss(4 * N + 8, 8 * N + 16);
  return q;
}

// The OL table: a(s), b(s) for s in [0, kMaxNorm], fitted over zero-mean parts of cap
// indicators (negative, like log-visibility) with half-angles spread uniformly in solid angle.
constexpr int kTable = 257;
constexpr double kMaxNorm = 32.0;

template <int N>
struct OlTable {
  std::vector<OlFit> fit;
  OlTable() : fit(kTable) {
    constexpr int kGauss = 96, kShapes = 48;
    std::vector<double> z(kGauss), w(kGauss);
    {
      const SphereQuadrature q =
          SphereQuadrature::gauss(kGauss, 1);  // nodes in z, weights 4 pi w/2
      for (int i = 0; i < kGauss; ++i) {
        z[i] = q.directions[i].z;
        w[i] = q.weights[i] / (2 * std::numbers::pi) * 2 * std::numbers::pi;  // = 2 pi * GL weight
      }
    }
    // Zonal shapes: ZH coefficients of -cap(theta), DC removed, unit norm; and their values.
    std::vector<std::array<double, N>> shape(kShapes);
    std::vector<std::vector<double>> value(kShapes, std::vector<double>(kGauss));
    for (int k = 0; k < kShapes; ++k) {
      const double solid =
          4 * std::numbers::pi * (k + 0.5) / kShapes * 0.5;  // caps up to a hemisphere
      const double theta = std::acos(1 - solid / (2 * std::numbers::pi));
      const Zonal<N> cap = zh_cap<N>(static_cast<float>(theta));
      double norm2 = 0;
      for (int l = 1; l < N; ++l) norm2 += double(cap[l]) * cap[l];
      for (int l = 0; l < N; ++l) shape[k][l] = l == 0 ? 0.0 : -cap[l] / std::sqrt(norm2);
      for (int i = 0; i < kGauss; ++i) {
        double p[N];
        legendre(z[i], N, p);
        double v = 0;
        for (int l = 1; l < N; ++l)
          v += shape[k][l] * std::sqrt((2 * l + 1) / (4 * std::numbers::pi)) * p[l];
        value[k][i] = v;
      }
    }
    for (int t = 0; t < kTable; ++t) {
      const double s = kMaxNorm * t / (kTable - 1);
      // a: mean of e^{f}; b: least-squares slope of the zero-mean part, <E, f^> / <f^, f^>.
      double a_sum = 0, num = 0, den = 0;
      for (int k = 0; k < kShapes; ++k) {
        double e_l[N] = {};
        for (int i = 0; i < kGauss; ++i) {
          double p[N];
          legendre(z[i], N, p);
          const double e = std::exp(s * value[k][i]) * w[i];
          for (int l = 0; l < N; ++l)
            e_l[l] += e * std::sqrt((2 * l + 1) / (4 * std::numbers::pi)) * p[l];
        }
        a_sum += e_l[0] / std::sqrt(4 * std::numbers::pi);
        for (int l = 1; l < N; ++l) num += e_l[l] * s * shape[k][l];
        den += s * s;
      }
      fit[t].a = static_cast<float>(a_sum / kShapes);
      fit[t].b = static_cast<float>(den > 0 ? num / den : 1.0);
    }
  }
};
}  // namespace

template <int N>
OlFit ol_fit(float norm) {
  static const OlTable<N> table;
  // NaN reads as 0 (a NaN input then fails exp_visibility's clamp, which zeroes it).
  const double x = (norm > 0 ? std::min<double>(norm, kMaxNorm) : 0.0) / kMaxNorm * (kTable - 1);
  const int i = std::min(static_cast<int>(x), kTable - 2);
  const float f = static_cast<float>(x - i);
  return {table.fit[i].a * (1 - f) + table.fit[i + 1].a * f,
          table.fit[i].b * (1 - f) + table.fit[i + 1].b * f};
}

template <int N>
Coeffs<N> log_clamped(const Coeffs<N>& f, float eps) {
  const float log_eps = std::log(eps);
  return project<N>(
      [&](const glm::vec3& d) {
        const float v = evaluate<N>(f, d);
        return v > eps ? std::log(v) : log_eps;
      },
      quadrature<N>());
}

template <int N>
Coeffs<N> exp_numeric(const Coeffs<N>& f) {
  return project<N>([&](const glm::vec3& d) { return std::exp(evaluate<N>(f, d)); },
                    quadrature<N>());
}

template <int N>
Coeffs<N> exp_ol(const Coeffs<N>& f) {
  float norm2 = 0;
  for (int i = 1; i < N * N; ++i) norm2 += f[i] * f[i];
  const OlFit fit = ol_fit<N>(std::sqrt(norm2));
  const float scale = std::exp(f[0] * kY0);  // e^{DC value}
  Coeffs<N> out;
  out[0] = scale * fit.a / kY0;  // a * (projection of the constant 1) = a * sqrt(4 pi)
  for (int i = 1; i < N * N; ++i) out[i] = scale * fit.b * f[i];
  return out;
}

template <int N>
Coeffs<N> exp_hyb(const Coeffs<N>& f, float ol_norm) {
  float norm2 = 0;
  for (int i = 1; i < N * N; ++i) norm2 += f[i] * f[i];
  const float norm = std::sqrt(norm2);
  int k = 0;
  // A norm whose square overflowed (inf) takes no squarings: the clamp handles the result.
  if (norm > ol_norm && std::isfinite(norm))
    k = static_cast<int>(std::ceil(std::log2(norm / ol_norm)));
  Coeffs<N> scaled = f;
  scaled[0] = 0;  // DC isolation: applied exactly at the end
  const float down = std::ldexp(1.0f, -k);
  for (int i = 1; i < N * N; ++i) scaled[i] *= down;
  Coeffs<N> g = exp_ol<N>(scaled);
  for (int s = 0; s < k; ++s) g = square<N>(g);
  const float dc = std::exp(f[0] * kY0);
  for (float& c : g) c *= dc;
  return g;
}

template <int N>
Coeffs<N> exp_visibility(const Coeffs<N>& log_visibility) {
  Coeffs<N> v = exp_hyb<N>(log_visibility);
  const float full = 1.0f / kY0;  // sqrt(4 pi): the DC of the constant 1
  if (!std::isfinite(v[0])) v.fill(0.0f);
  v[0] = std::clamp(v[0], 0.0f, full);
  float rest2 = 0;
  for (int i = 1; i < N * N; ++i) rest2 += v[i] * v[i];
  const float max_rest2 = std::max(0.0f, full * v[0] - v[0] * v[0]);
  if (!(rest2 <= max_rest2)) {  // also catches NaN
    const float k = rest2 > 0 && std::isfinite(rest2) ? std::sqrt(max_rest2 / rest2) : 0.0f;
    for (int i = 1; i < N * N; ++i) v[i] = std::isfinite(v[i]) ? v[i] * k : 0.0f;
  }
  return v;
}

#define PENUMBRA_EXPLOG_INSTANTIATE(N)                        \
  template OlFit ol_fit<N>(float);                            \
  template Coeffs<N> log_clamped<N>(const Coeffs<N>&, float); \
  template Coeffs<N> exp_numeric<N>(const Coeffs<N>&);        \
  template Coeffs<N> exp_ol<N>(const Coeffs<N>&);             \
  template Coeffs<N> exp_hyb<N>(const Coeffs<N>&, float);     \
  template Coeffs<N> exp_visibility<N>(const Coeffs<N>&);
PENUMBRA_EXPLOG_INSTANTIATE(2)
PENUMBRA_EXPLOG_INSTANTIATE(3)
PENUMBRA_EXPLOG_INSTANTIATE(4)
PENUMBRA_EXPLOG_INSTANTIATE(5)
PENUMBRA_EXPLOG_INSTANTIATE(6)
#undef PENUMBRA_EXPLOG_INSTANTIATE

}  // namespace penumbra::sh
