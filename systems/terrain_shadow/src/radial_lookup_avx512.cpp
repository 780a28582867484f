// RadialHorizonSweep::horizons8's vector path (radial_horizon_sweep.cpp) on sixteen AVX-512
// lanes: the same operations per lane in the same order (so the same floats), one set-up and
// two 16-element gathers for the texels of a row on one side of the foot. Chosen at run time by
// horizons16 (sweep_isa()).
#include "radial_lookup.h"

#include <cmath>

#include "fast_math.h"  // before the AVX-512 region: its inline functions stay baseline code

#ifdef __AVX2__
#include "avx512_target_begin.h"  // to avx512_target_end.h below

#include <immintrin.h>

#include "fast_math16.h"

namespace penumbra::terrain_shadow::detail::avx512 {

unsigned radial_horizons16(const RadialSideView& side, int index, float foot_x, float foot_y,
                           int x0, int y, float* out) {
  const float ry = static_cast<float>(y) - foot_y;
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i x = _mm512_add_epi32(_mm512_set1_epi32(x0), iota);
  const __m512 rx = _mm512_sub_ps(_mm512_maskz_cvtepi32_ps(kAll, x), _mm512_set1_ps(foot_x));
  const __m512 ru = side.x_major ? _mm512_abs_ps(rx) : _mm512_set1_ps(std::fabs(ry));
  const __m512 rv = side.x_major ? _mm512_set1_ps(ry) : rx;
  const __m512 jf = _mm512_fmadd_ps(_mm512_div_ps(rv, ru), _mm512_set1_ps(side.lines_per_slope),
                                    _mm512_set1_ps(-static_cast<float>(side.j_lo)));
  const __m512i l0 = _mm512_maskz_min_epi32(
      kAll,
      _mm512_maskz_max_epi32(
          kAll,
          _mm512_maskz_cvttps_epi32(kAll, _mm512_maskz_roundscale_ps(kAll, jf, _MM_FROUND_FLOOR)),
          _mm512_setzero_si512()),
      _mm512_set1_epi32(side.lines - 2));
  const __m512 t = _mm512_maskz_min_ps(
      kAll,
      _mm512_maskz_max_ps(kAll, _mm512_sub_ps(jf, _mm512_maskz_cvtepi32_ps(kAll, l0)),
                          _mm512_setzero_ps()),
      _mm512_set1_ps(1.0f));
  const __m512i k = side.x_major
                        ? _mm512_mullo_epi32(_mm512_set1_epi32(side.sign),
                                             _mm512_sub_epi32(x, _mm512_set1_epi32(side.u_first)))
                        : _mm512_set1_epi32(side.sign * (y - side.u_first));
  // The lanes on this side (as horizon(): |rx| >= |ry| on sides 0 and 1, by the sign of rx;
  // else 2 and 3, by the sign of ry; the foot's own texel on none), inside its columns.
  const __m512 ary = _mm512_set1_ps(std::fabs(ry)), zero = _mm512_setzero_ps();
  __mmask16 lanes;
  if (index == 0)
    lanes = _mm512_cmp_ps_mask(rx, zero, _CMP_GT_OQ) & _mm512_cmp_ps_mask(rx, ary, _CMP_GE_OQ);
  else if (index == 1)
    lanes = _mm512_cmp_ps_mask(rx, zero, _CMP_LT_OQ) &
            _mm512_cmp_ps_mask(_mm512_sub_ps(zero, rx), ary, _CMP_GE_OQ);
  else
    lanes = (ry > 0) == (index == 2) ? _mm512_cmp_ps_mask(_mm512_abs_ps(rx), ary, _CMP_LT_OQ) : 0;
  lanes &= _mm512_cmpge_epi32_mask(k, _mm512_setzero_si512()) &
           _mm512_cmplt_epi32_mask(k, _mm512_set1_epi32(side.columns));
  if (lanes == 0) return 0;
  // at(line, k) = angle[((line >> 3) columns + k) 8 + (line & 7)]
  auto slot = [&](__m512i line) {
    return _mm512_add_epi32(
        _mm512_maskz_slli_epi32(
            kAll,
            _mm512_add_epi32(_mm512_mullo_epi32(_mm512_maskz_srli_epi32(kAll, line, 3),
                                                _mm512_set1_epi32(side.columns)),
                             k),
            3),
        _mm512_and_si512(line, _mm512_set1_epi32(7)));
  };
  const __m512 lo = _mm512_mask_i32gather_ps(zero, lanes, slot(l0), side.angle, 4);
  const __m512 hi = _mm512_mask_i32gather_ps(
      zero, lanes, slot(_mm512_add_epi32(l0, _mm512_set1_epi32(1))), side.angle, 4);
  // A NaN line beside a texel: horizon() decides (it may march the texel's own ray).
  lanes &= _mm512_cmp_ps_mask(lo, hi, _CMP_ORD_Q);
  _mm512_mask_storeu_ps(out, lanes, _mm512_fmadd_ps(t, _mm512_sub_ps(hi, lo), lo));
  return lanes;
}

}  // namespace penumbra::terrain_shadow::detail::avx512

#include "avx512_target_end.h"
#endif
