// Internal: fast_math.h's 8-lane helpers on sixteen AVX-512 lanes, the same operations in the
// same order (so the same floats, lane for lane), for the dispatched AVX-512 kernels only:
// include it between avx512_target_begin.h and avx512_target_end.h, after fast_math.h (whose
// out-of-line functions must be compiled for the baseline; check_isa_isolation.py checks).
#pragma once

#include <immintrin.h>

#include <cstddef>
#include <iterator>

#include "fast_math.h"

namespace penumbra::terrain_shadow::detail::avx512 {

// Every lane, as a mask: GCC 12's unmasked forms of some 512-bit intrinsics pass an undefined
// vector through and warn (-Wmaybe-uninitialized, fixed in GCC 13); the zero-masked forms with
// all lanes are the same instructions.
inline constexpr __mmask16 kAll = 0xffff;

// horner8 on 16 lanes.
template <std::size_t K>
[[gnu::always_inline]] inline __m512 horner16(__m512 x, const float (&c)[K]) {
  __m512 p = _mm512_set1_ps(c[0]);
  for (std::size_t i = 1; i < K; ++i) p = _mm512_fmadd_ps(p, x, _mm512_set1_ps(c[i]));
  return p;
}

// fast_atan_unit8 on 16 lanes: z in [0, 1] -> atan(z).
[[gnu::always_inline]] inline __m512 fast_atan_unit16(__m512 z) {
  return _mm512_mul_ps(z, horner16(_mm512_mul_ps(z, z), kAtanPoly));
}

// fast_atan8 on 16 lanes, in place (by reference: no 512-bit values cross a function boundary).
[[gnu::always_inline]] inline void fast_atan16(__m512& x) {
  const __m512 sign = _mm512_set1_ps(-0.0f), one = _mm512_set1_ps(1.0f);
  const __m512 a = _mm512_andnot_ps(sign, x);
  const __mmask16 inv = _mm512_cmp_ps_mask(a, one, _CMP_GT_OQ);
  const __m512 r = fast_atan_unit16(_mm512_maskz_min_ps(kAll, a, _mm512_div_ps(one, a)));
  x = _mm512_or_ps(_mm512_mask_blend_ps(inv, r, _mm512_sub_ps(_mm512_set1_ps(1.57079632679f), r)),
                   _mm512_and_ps(sign, x));
}

// fast_atan_ratio8 on 16 lanes: atan(num / den) for den > 0 with one division.
[[gnu::always_inline]] inline __m512 fast_atan_ratio16(__m512 num, __m512 den) {
  const __m512 sign = _mm512_set1_ps(-0.0f);
  const __m512 a = _mm512_andnot_ps(sign, num);
  const __mmask16 inv = _mm512_cmp_ps_mask(a, den, _CMP_GT_OQ);
  const __m512 r = fast_atan_unit16(
      _mm512_div_ps(_mm512_maskz_min_ps(kAll, a, den), _mm512_maskz_max_ps(kAll, a, den)));
  const __m512 t = _mm512_mask_blend_ps(inv, r, _mm512_sub_ps(_mm512_set1_ps(1.57079632679f), r));
  return _mm512_or_ps(t, _mm512_and_ps(sign, num));
}

// fast_sin8 and fast_cos8 on 16 lanes ([-pi/2, pi/2]).
[[gnu::always_inline]] inline __m512 fast_sin16(__m512 x) {
  const __m512 x2 = _mm512_mul_ps(x, x);
  return _mm512_fmadd_ps(_mm512_mul_ps(x, x2), horner16(x2, kSinPoly), x);
}
[[gnu::always_inline]] inline __m512 fast_cos16(__m512 x) {
  return horner16(_mm512_mul_ps(x, x), kCosPoly);
}

// lanes.h's transpose8 on a 16 x 16 block: m[i] lane j becomes m[j] lane i (unpacks within
// 128-bit lanes, then two rounds of 128-bit lane shuffles: 64 shuffles, against 96 for the
// same floats as four 8 x 8 transposes).
[[gnu::always_inline]] inline void transpose16(__m512 m[16]) {
  __m512 t[16], u[16];
  for (int i = 0; i < 16; i += 2) {
    t[i] = _mm512_maskz_unpacklo_ps(kAll, m[i], m[i + 1]);
    t[i + 1] = _mm512_maskz_unpackhi_ps(kAll, m[i], m[i + 1]);
  }
  // u[4q + r], 128-bit lane j: rows 4q..4q+3 of column 4j + r.
  for (int i = 0; i < 16; i += 4) {
    u[i] = _mm512_maskz_shuffle_ps(kAll, t[i], t[i + 2], _MM_SHUFFLE(1, 0, 1, 0));
    u[i + 1] = _mm512_maskz_shuffle_ps(kAll, t[i], t[i + 2], _MM_SHUFFLE(3, 2, 3, 2));
    u[i + 2] = _mm512_maskz_shuffle_ps(kAll, t[i + 1], t[i + 3], _MM_SHUFFLE(1, 0, 1, 0));
    u[i + 3] = _mm512_maskz_shuffle_ps(kAll, t[i + 1], t[i + 3], _MM_SHUFFLE(3, 2, 3, 2));
  }
  // Column 4j + r gathers lane j of u[r], u[4 + r], u[8 + r], u[12 + r].
  for (int r = 0; r < 4; ++r) {
    t[r] = _mm512_maskz_shuffle_f32x4(kAll, u[r], u[4 + r], 0x88);
    t[4 + r] = _mm512_maskz_shuffle_f32x4(kAll, u[r], u[4 + r], 0xdd);
    t[8 + r] = _mm512_maskz_shuffle_f32x4(kAll, u[8 + r], u[12 + r], 0x88);
    t[12 + r] = _mm512_maskz_shuffle_f32x4(kAll, u[8 + r], u[12 + r], 0xdd);
  }
  for (int r = 0; r < 4; ++r) {
    m[r] = _mm512_maskz_shuffle_f32x4(kAll, t[r], t[8 + r], 0x88);
    m[8 + r] = _mm512_maskz_shuffle_f32x4(kAll, t[r], t[8 + r], 0xdd);
    m[4 + r] = _mm512_maskz_shuffle_f32x4(kAll, t[4 + r], t[12 + r], 0x88);
    m[12 + r] = _mm512_maskz_shuffle_f32x4(kAll, t[4 + r], t[12 + r], 0xdd);
  }
}

}  // namespace penumbra::terrain_shadow::detail::avx512
