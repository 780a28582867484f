// Real spherical harmonics: basis, coefficient vectors, evaluation.
//
// Conventions (pinned by tests/sh/basis_test.cpp):
//  - real SH y_i with index i = l(l+1) + m, l = 0..N-1, m = -l..l; N bands give N*N coefficients;
//  - no Condon-Shortley phase, band 1 ordered (y, z, x): y_1^-1 = +sqrt(3/4pi) y
//    ([Ambrosj16] appendix A; [Giraud] eq. 3-5);
//  - directions are unit vectors in a right-handed, z-up frame (z is the height-field normal).
// The band count N is a template parameter, 2..6; kDefaultBands (4, 16 coefficients) is what
// all the seed documents use. Everything is float.
#pragma once

#include <array>
#include <cstddef>

#include <glm/vec3.hpp>

namespace penumbra::sh {

inline constexpr int kDefaultBands = 4;
inline constexpr int kMaxBands = 6;

template <int N>
inline constexpr int kCount = N * N;

constexpr int index(int l, int m) { return l * (l + 1) + m; }

// Coefficients of one function (one colour channel).
template <int N>
using Coeffs = std::array<float, static_cast<std::size_t>(N * N)>;

// One coefficient vector per colour channel (r, g, b).
template <int N>
using CoeffsRgb = std::array<Coeffs<N>, 3>;

// y_i(dir) for i < N*N. `dir` must be unit length.
template <int N>
void eval_basis(const glm::vec3& dir, float* out);

template <int N>
Coeffs<N> eval_basis(const glm::vec3& dir) {
  Coeffs<N> out;
  eval_basis<N>(dir, out.data());
  return out;
}

// Structure-of-arrays batch: directions given as x[], y[], z[] (unit length); writes
// out[i * count + d] = y_i(dir_d), one row of `count` values per coefficient. Runs 8 directions
// per step on vector lanes (about 3x the scalar path). Performance note: with `count` a
// multiple of 1024 the rows are 4 KiB apart and every store of a step lands in one L1 set;
// pad `count` (e.g. 1000 or 1032) when calling it in a hot loop.
template <int N>
void eval_basis_batch(const float* x, const float* y, const float* z, std::size_t count, float* out);

// The band-limited function at `dir`: sum_i f_i y_i(dir) ([Giraud] eq. 4).
template <int N>
float evaluate(const Coeffs<N>& f, const glm::vec3& dir);

// Integral over the sphere of the product of two band-limited functions.
template <int N>
float dot(const Coeffs<N>& a, const Coeffs<N>& b) {
  float s = 0;
  for (int i = 0; i < N * N; ++i) s += a[i] * b[i];
  return s;
}

}  // namespace penumbra::sh
