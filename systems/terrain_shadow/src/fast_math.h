// Internal: the terrain shadow system's fast math, in one place: arctangent (and asin, acos
// through it) and sine to float precision without a libm call (horizon angles are taken for
// millions of samples a frame). Arctangent: Odd minimax-weighted polynomial of degree 15 on [0, 1],
// fitted by iteratively reweighted least squares; measured max error 1.1e-7 rad over [0, 1] in
// float. |x| > 1 uses atan(x) = sign(x) pi/2 - atan(1/x).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace penumbra::terrain_shadow::detail {

// The system's angle constants, in one place (float: the kernels' precision).
inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kHalfPi = kPi / 2;
inline constexpr float kTwoPi = 2 * kPi;

// fast_atan's polynomial in z^2, highest power first (the lane versions' Horner order).
inline constexpr float kAtanPoly[] = {-4.051978102e-03f, 2.185325950e-02f,  -5.589779900e-02f,
                                      9.641089470e-02f,  -1.390817735e-01f, 1.994647099e-01f,
                                      -3.332985206e-01f, 9.999993333e-01f};

inline float fast_atan(float x) {
  const float a = std::fabs(x);
  const bool inv = a > 1.0f;
  const float z = std::min(a, 1.0f / a);  // branch-free, so loops over arrays vectorise
  const float z2 = z * z;
  float p = -4.051978102e-03f;
  p = p * z2 + 2.185325950e-02f;
  p = p * z2 - 5.589779900e-02f;
  p = p * z2 + 9.641089470e-02f;
  p = p * z2 - 1.390817735e-01f;
  p = p * z2 + 1.994647099e-01f;
  p = p * z2 - 3.332985206e-01f;
  p = p * z2 + 9.999993333e-01f;
  float r = z * p;
  if (inv) r = 1.57079632679f - r;
  return std::copysign(r, x);
}

// The lanes' sine and cosine polynomials in x^2 (fast_sin's and fast_cos's coefficients):
// sin x = x + x^3 P(x^2), cos x = Q(x^2).
inline constexpr float kSinPoly[] = {-2.50521084e-8f, 2.75573192e-6f, -1.98412698e-4f,
                                     8.33333333e-3f, -1.66666667e-1f};
inline constexpr float kCosPoly[] = {
    2.08767570e-9f, -2.75573192e-7f, 2.48015873e-5f, -1.38888889e-3f, 4.16666667e-2f, -0.5f, 1.0f};

#ifdef __AVX2__
// The 8-lane helpers are always inlined: sweep_lanes_avx512.cpp compiles them for AVX-512 into
// its kernels, and no out-of-line copy of that may be the one the linker keeps.
// c[0] x^(K-1) + ... + c[K-1] by Horner's rule on 8 lanes (the scalar polynomials' order).
template <std::size_t K>
[[gnu::always_inline]] inline __m256 horner8(__m256 x, const float (&c)[K]) {
  __m256 p = _mm256_set1_ps(c[0]);
  for (std::size_t i = 1; i < K; ++i) p = _mm256_fmadd_ps(p, x, _mm256_set1_ps(c[i]));
  return p;
}

// fast_atan's polynomial on 8 lanes: z in [0, 1] -> atan(z).
[[gnu::always_inline]] inline __m256 fast_atan_unit8(__m256 z) {
  return _mm256_mul_ps(z, horner8(_mm256_mul_ps(z, z), kAtanPoly));
}

// sin and cos on [-pi/2, pi/2] on 8 lanes (fast_sin's polynomial; cos by Taylor to x^12):
// errors under 6e-8.
[[gnu::always_inline]] inline __m256 fast_sin8(__m256 x) {
  const __m256 x2 = _mm256_mul_ps(x, x);
  return _mm256_fmadd_ps(_mm256_mul_ps(x, x2), horner8(x2, kSinPoly), x);
}
[[gnu::always_inline]] inline __m256 fast_cos8(__m256 x) {
  return horner8(_mm256_mul_ps(x, x), kCosPoly);
}

// atan(num / den) for den > 0 on 8 lanes with one division (min / max of |num| and den).
[[gnu::always_inline]] inline __m256 fast_atan_ratio8(__m256 num, __m256 den) {
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 a = _mm256_andnot_ps(sign, num);
  const __m256 inv = _mm256_cmp_ps(a, den, _CMP_GT_OQ);
  const __m256 r = fast_atan_unit8(_mm256_div_ps(_mm256_min_ps(a, den), _mm256_max_ps(a, den)));
  const __m256 t = _mm256_blendv_ps(r, _mm256_sub_ps(_mm256_set1_ps(1.57079632679f), r), inv);
  return _mm256_or_ps(t, _mm256_and_ps(sign, num));
}
#endif

#ifdef __AVX2__
// fast_atan on 8 lanes (the same operations, so the same results). -inf gives -pi/2.
[[gnu::always_inline]] inline __m256 fast_atan8(__m256 x) {
  const __m256 sign = _mm256_set1_ps(-0.0f), one = _mm256_set1_ps(1.0f);
  const __m256 a = _mm256_andnot_ps(sign, x);
  const __m256 inv = _mm256_cmp_ps(a, one, _CMP_GT_OQ);
  const __m256 r = fast_atan_unit8(_mm256_min_ps(a, _mm256_div_ps(one, a)));
  return _mm256_or_ps(_mm256_blendv_ps(r, _mm256_sub_ps(_mm256_set1_ps(1.57079632679f), r), inv),
                      _mm256_and_ps(sign, x));
}
#endif

// In place over an array, 8 lanes at a time where AVX2 is available (fast_atan8, so the
// results are identical). -inf gives -pi/2.
inline void fast_atan_array(float* v, std::size_t n) {
  std::size_t i = 0;
#ifdef __AVX2__
  for (; i + 8 <= n; i += 8) _mm256_storeu_ps(v + i, fast_atan8(_mm256_loadu_ps(v + i)));
#endif
  for (; i < n; ++i) v[i] = fast_atan(v[i]);
}

// asin and acos through fast_atan (1.1e-7 rad): |x| <= 1; +-1 give +-pi/2 (x / 0 = +-inf).
inline float fast_asin(float x) {
  return fast_atan(x / std::sqrt(std::max((1 - x) * (1 + x), 0.0f)));
}
inline float fast_acos(float x) {
  return kHalfPi - fast_asin(x);
}

// sin on [-pi/2, pi/2]: odd minimax-style polynomial (Taylor to x^11), error < 6e-8.
inline float fast_sin(float x) {
  const float x2 = x * x;
  float p = -2.50521084e-8f;
  p = p * x2 + 2.75573192e-6f;
  p = p * x2 - 1.98412698e-4f;
  p = p * x2 + 8.33333333e-3f;
  p = p * x2 - 1.66666667e-1f;
  return x + x * x2 * p;
}

// cos on [-pi/2, pi/2] (fast_cos8's polynomial: Taylor to x^12), error < 6e-8.
inline float fast_cos(float x) {
  const float x2 = x * x;
  float p = 2.08767570e-9f;
  p = p * x2 - 2.75573192e-7f;
  p = p * x2 + 2.48015873e-5f;
  p = p * x2 - 1.38888889e-3f;
  p = p * x2 + 4.16666667e-2f;
  p = p * x2 - 0.5f;
  return p * x2 + 1.0f;
}

// atan(num / den) for den >= 0 (not both zero) with one division, as fast_atan_ratio8.
inline float fast_atan_ratio(float num, float den) {
  const float a = std::fabs(num);
  const float r = fast_atan(std::min(a, den) / std::max(a, den));
  return std::copysign(a > den ? 1.57079632679f - r : r, num);
}

}  // namespace penumbra::terrain_shadow::detail
