#include "penumbra/sh/rotation.h"

#include <cmath>
#include <cstdlib>
#include <numbers>

namespace penumbra::sh {

template <int N>
Coeffs<N> rotate_zh(const Zonal<N>& z, const glm::vec3& axis) {
  const Coeffs<N> y = eval_basis<N>(axis);
  Coeffs<N> out{};
  for (int l = 0; l < N; ++l) {
    const float k = std::sqrt(4 * std::numbers::pi_v<float> / static_cast<float>(2 * l + 1)) * z[l];
    for (int m = -l; m <= l; ++m) out[index(l, m)] = k * y[index(l, m)];
  }
  return out;
}

template <int N>
Coeffs<N> rotate_z(const Coeffs<N>& f, float angle) {
  Coeffs<N> out = f;
  const float c1 = std::cos(angle), s1 = std::sin(angle);
  float c = 1, s = 0;
  for (int m = 1; m < N; ++m) {
    const float cm = c * c1 - s * s1;  // cos(m a), sin(m a) by the angle-addition recurrence
    s = s * c1 + c * s1;
    c = cm;
    for (int l = m; l < N; ++l) {
      const float a = f[index(l, m)], b = f[index(l, -m)];  // cos(m phi) and sin(m phi) parts
      out[index(l, m)] = a * c - b * s;
      out[index(l, -m)] = a * s + b * c;
    }
  }
  return out;
}

namespace {
// Dense per-band matrix view with signed indices.
struct BandView {
  const float* data;
  int l;
  float operator()(int m, int n) const { return data[(m + l) * (2 * l + 1) + (n + l)]; }
};

// Ivanic-Ruedenberg helper P (their eq. 8.x, table 2).
float P(int i, int l, int a, int b, const BandView& r1, const BandView& prev) {
  if (b == l) return r1(i, 1) * prev(a, l - 1) - r1(i, -1) * prev(a, -l + 1);
  if (b == -l) return r1(i, 1) * prev(a, -l + 1) + r1(i, -1) * prev(a, l - 1);
  return r1(i, 0) * prev(a, b);
}
}  // namespace

template <int N>
Rotation<N>::Rotation(const glm::mat3& r) {
  int size = 0;
  for (int l = 0; l < N; ++l) {
    offset_[l] = size;
    size += (2 * l + 1) * (2 * l + 1);
  }
  m_.assign(size, 0.0f);
  m_[0] = 1;
  if (N < 2) return;
  // Band 1 in (y, z, x) order; glm is column-major: r[col][row].
  static constexpr int axis[3] = {1, 2, 0};  // m = -1, 0, 1
  float* b1 = m_.data() + offset_[1];
  for (int m = -1; m <= 1; ++m) {
    for (int n = -1; n <= 1; ++n) b1[(m + 1) * 3 + (n + 1)] = r[axis[n + 1]][axis[m + 1]];
  }
  const BandView r1{b1, 1};
  for (int l = 2; l < N; ++l) {
    const BandView prev{m_.data() + offset_[l - 1], l - 1};
    float* out = m_.data() + offset_[l];
    for (int m = -l; m <= l; ++m) {
      for (int n = -l; n <= l; ++n) {
        const int am = std::abs(m);
        const double d = m == 0 ? 1.0 : 0.0;
        const double denom = std::abs(n) == l ? (2.0 * l) * (2.0 * l - 1) : double(l + n) * (l - n);
        const double u = std::sqrt(double(l + m) * (l - m) / denom);
        const double v = 0.5 * std::sqrt((1 + d) * (l + am - 1) * (l + am) / denom) * (1 - 2 * d);
        const double w = -0.5 * std::sqrt(double(l - am - 1) * (l - am) / denom) * (1 - d);
        double value = 0;
        if (u != 0) value += u * P(0, l, m, n, r1, prev);
        if (v != 0) {
          double V;
          if (m == 0) {
            V = P(1, l, 1, n, r1, prev) + P(-1, l, -1, n, r1, prev);
          } else if (m > 0) {
            const double d1 = m == 1 ? 1.0 : 0.0;
            V = P(1, l, m - 1, n, r1, prev) * std::sqrt(1 + d1) - P(-1, l, -m + 1, n, r1, prev) * (1 - d1);
          } else {
            const double d1 = m == -1 ? 1.0 : 0.0;
            V = P(1, l, m + 1, n, r1, prev) * (1 - d1) + P(-1, l, -m - 1, n, r1, prev) * std::sqrt(1 + d1);
          }
          value += v * V;
        }
        if (w != 0) {
          const double W = m > 0 ? P(1, l, m + 1, n, r1, prev) + P(-1, l, -m - 1, n, r1, prev)
                                 : P(1, l, m - 1, n, r1, prev) - P(-1, l, -m + 1, n, r1, prev);
          value += w * W;
        }
        out[(m + l) * (2 * l + 1) + (n + l)] = static_cast<float>(value);
      }
    }
  }
}

template <int N>
float Rotation<N>::band(int l, int m, int n) const {
  return m_[offset_[l] + (m + l) * (2 * l + 1) + (n + l)];
}

template <int N>
Coeffs<N> Rotation<N>::apply(const Coeffs<N>& f) const {
  Coeffs<N> out{};
  for (int l = 0; l < N; ++l) {
    const int size = 2 * l + 1, base = l * l;
    const float* mat = m_.data() + offset_[l];
    for (int r = 0; r < size; ++r) {
      float s = 0;
      for (int c = 0; c < size; ++c) s += mat[r * size + c] * f[base + c];
      out[base + r] = s;
    }
  }
  return out;
}

#define PENUMBRA_ROT_INSTANTIATE(N)                                  \
  template Coeffs<N> rotate_zh<N>(const Zonal<N>&, const glm::vec3&); \
  template Coeffs<N> rotate_z<N>(const Coeffs<N>&, float);           \
  template class Rotation<N>;
PENUMBRA_ROT_INSTANTIATE(2)
PENUMBRA_ROT_INSTANTIATE(3)
PENUMBRA_ROT_INSTANTIATE(4)
PENUMBRA_ROT_INSTANTIATE(5)
PENUMBRA_ROT_INSTANTIATE(6)
#undef PENUMBRA_ROT_INSTANTIATE

}  // namespace penumbra::sh
