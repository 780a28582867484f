// cap_first_pass16's and cap_chords16's AVX-512 kernels (cap_transfer.h): cap_lanes8,
// front_lens8 and general_chords8 of cap_transfer_lanes.cpp on sixteen lanes, operation for
// operation (so the same floats), the lane masks in mask registers. Chosen at run time by
// cap_first_pass16 and cap_chords16 (sweep_isa()).
#include "penumbra/systems/terrain_shadow/cap_transfer.h"

#include <algorithm>
#include <cstddef>

#include "cap_chords.h"
#include "fast_math.h"

#ifdef __AVX2__
#include "avx512_target_begin.h"  // to avx512_target_end.h below

#include <immintrin.h>

#include "fast_math16.h"

namespace penumbra::terrain_shadow::detail::avx512 {
namespace {

// sqrt, max and min through their zero-masking forms with every lane (fast_math16.h's kAll).
[[gnu::always_inline]] inline __m512 sqrt16(__m512 x) {
  return _mm512_maskz_sqrt_ps(kAll, x);
}
[[gnu::always_inline]] inline __m512 max16(__m512 a, __m512 b) {
  return _mm512_maskz_max_ps(kAll, a, b);
}
[[gnu::always_inline]] inline __m512 min16(__m512 a, __m512 b) {
  return _mm512_maskz_min_ps(kAll, a, b);
}

// make_light_cap on sixteen lanes (cap_lanes8's first lines): the receivers' vectors to the
// centre and normals, loaded, and their caps.
struct Cap16 {
  __m512 dx, dy, dz, nx, ny, nz;
  __m512 rho, nc, plane, cos_e, sin_e, cos_half;
  __m512 bottom, top;        // the cap's lowest and highest elevation (sines)
  __mmask16 outside, front;  // |d| > radius; n.d > -radius
  __mmask16 lit;             // outside, in front and n.c > -rho
};
template <class Lanes>
[[gnu::always_inline]] inline void load_cap16(const Lanes& in, float radius, Cap16& c) {
  c.dx = _mm512_loadu_ps(in.dx), c.dy = _mm512_loadu_ps(in.dy), c.dz = _mm512_loadu_ps(in.dz);
  c.nx = _mm512_loadu_ps(in.nx), c.ny = _mm512_loadu_ps(in.ny), c.nz = _mm512_loadu_ps(in.nz);
  const __m512 r = _mm512_set1_ps(radius), one = _mm512_set1_ps(1.0f);
  const __m512 zero = _mm512_setzero_ps();
  const __m512 plane2 = _mm512_fmadd_ps(c.dy, c.dy, _mm512_mul_ps(c.dx, c.dx));
  const __m512 dist = sqrt16(_mm512_fmadd_ps(c.dz, c.dz, plane2));
  c.outside = _mm512_cmp_ps_mask(dist, r, _CMP_GT_OQ);
  const __m512 inv = _mm512_div_ps(one, dist);
  const __m512 nd =
      _mm512_fmadd_ps(c.nz, c.dz, _mm512_fmadd_ps(c.ny, c.dy, _mm512_mul_ps(c.nx, c.dx)));
  c.front = _mm512_cmp_ps_mask(nd, _mm512_sub_ps(zero, r), _CMP_GT_OQ);
  c.rho = _mm512_mul_ps(r, inv), c.nc = _mm512_mul_ps(nd, inv);
  c.plane = sqrt16(plane2);
  c.cos_e = _mm512_mul_ps(c.plane, inv), c.sin_e = _mm512_mul_ps(c.dz, inv);
  c.cos_half =
      _mm512_mul_ps(sqrt16(_mm512_mul_ps(_mm512_sub_ps(dist, r), _mm512_add_ps(dist, r))), inv);
  const __mmask16 pole = _mm512_cmp_ps_mask(c.rho, c.cos_e, _CMP_GT_OQ);
  c.bottom = _mm512_mask_blend_ps(
      pole & _mm512_cmp_ps_mask(c.sin_e, zero, _CMP_LT_OQ),
      _mm512_fmsub_ps(c.sin_e, c.cos_half, _mm512_mul_ps(c.cos_e, c.rho)), _mm512_set1_ps(-1.0f));
  c.top = _mm512_mask_blend_ps(pole & _mm512_cmp_ps_mask(c.sin_e, zero, _CMP_GT_OQ),
                               _mm512_fmadd_ps(c.sin_e, c.cos_half, _mm512_mul_ps(c.cos_e, c.rho)),
                               one);
  c.lit = c.outside & c.front & _mm512_cmp_ps_mask(c.nc, _mm512_sub_ps(zero, c.rho), _CMP_GT_OQ);
}

// The cap's frame (cap_transfer): side = (-pd.y, pd.x, 0), up = (-sin_e pd, cos_e); the normal's
// components ns (side), nw (pd) and nu (up).
[[gnu::always_inline]] inline void cap_frame16(const Cap16& c, __m512& ns, __m512& nw, __m512& nu) {
  const __m512 one = _mm512_set1_ps(1.0f);
  const __mmask16 has_plane = _mm512_cmp_ps_mask(c.plane, _mm512_setzero_ps(), _CMP_GT_OQ);
  const __m512 inv_plane = _mm512_div_ps(one, max16(c.plane, _mm512_set1_ps(1e-30f)));
  const __m512 pdx = _mm512_mask_blend_ps(has_plane, one, _mm512_mul_ps(c.dx, inv_plane));
  const __m512 pdy = _mm512_maskz_mov_ps(has_plane, _mm512_mul_ps(c.dy, inv_plane));
  ns = _mm512_fmsub_ps(c.ny, pdx, _mm512_mul_ps(c.nx, pdy));
  nw = _mm512_fmadd_ps(c.ny, pdy, _mm512_mul_ps(c.nx, pdx));
  nu = _mm512_fmsub_ps(c.nz, c.cos_e, _mm512_mul_ps(c.sin_e, nw));
}

// front_lens8 (cap_chords.h's lens) on 16 lanes.
[[gnu::always_inline]] inline __m512 front_lens16(__m512 rho, __m512 cos_half, __m512 nc, __m512 nz,
                                                  __m512 nw, __m512 nu, __m512 sin_e, __m512 cos_e,
                                                  __m512 omega, __m512 sin_o) {
  const __m512 one = _mm512_set1_ps(1.0f), zero = _mm512_setzero_ps(), half = _mm512_set1_ps(0.5f);
  const __m512 two = _mm512_set1_ps(2.0f), tiny = _mm512_set1_ps(1e-30f);
  const __m512 rho2 = _mm512_mul_ps(rho, rho);
  const __m512 omc = _mm512_div_ps(rho2, _mm512_add_ps(one, cos_half));  // 1 - cos(beta)
  const __m512 cos_o = fast_cos16(omega);
  const __m512 d_sin = _mm512_sub_ps(sin_o, sin_e), d_cos = _mm512_sub_ps(cos_e, cos_o);
  const __m512 cphi = min16(max16(_mm512_div_ps(_mm512_fmadd_ps(sin_e, omc, d_sin),
                                                max16(_mm512_mul_ps(rho, cos_e), tiny)),
                                  _mm512_set1_ps(-1.0f)),
                            one);
  const __m512 sphi =
      sqrt16(max16(_mm512_mul_ps(_mm512_sub_ps(one, cphi), _mm512_add_ps(one, cphi)), zero));
  const __m512 phi = _mm512_sub_ps(_mm512_set1_ps(kHalfPi), fast_atan_ratio16(cphi, sphi));
  const __m512 chord2 = _mm512_fmadd_ps(d_sin, d_sin, _mm512_mul_ps(d_cos, d_cos));
  const __m512 k = min16(max16(_mm512_div_ps(_mm512_fnmadd_ps(half, chord2, omc),
                                             max16(_mm512_mul_ps(cos_o, cos_e), tiny)),
                               zero),
                         two);
  const __m512 hk = _mm512_mul_ps(half, k);
  const __m512 psi =
      _mm512_mul_ps(two, fast_atan_ratio16(sqrt16(hk), sqrt16(_mm512_sub_ps(one, hk))));
  const __m512 spsi = sqrt16(_mm512_mul_ps(k, _mm512_sub_ps(two, k)));
  const __m512 ends =
      _mm512_fnmadd_ps(d_cos, nz, _mm512_fnmadd_ps(d_sin, nw, _mm512_mul_ps(omc, nu)));
  const __m512 arcs =
      _mm512_fmadd_ps(_mm512_mul_ps(_mm512_sub_ps(psi, spsi), _mm512_mul_ps(cos_o, cos_o)), nz,
                      _mm512_mul_ps(_mm512_mul_ps(phi, rho2), nc));
  return max16(_mm512_fmadd_ps(_mm512_mul_ps(rho, sphi), ends, arcs), zero);
}

// general_chords8 (caps the tangent plane cuts) on 16 lanes.
[[gnu::always_inline]] inline __m512 general_chords16(__m512 rho, __m512 cos_half, __m512 nc,
                                                      __m512 ns, __m512 nu, __m512 sin_e,
                                                      __m512 cos_e, const __m512* chord_a,
                                                      int strips) {
  const __m512 one = _mm512_set1_ps(1.0f), zero = _mm512_setzero_ps();
  const __m512 sign = _mm512_set1_ps(-0.0f), pi = _mm512_set1_ps(kPi);
  const __m512 half_pi = _mm512_set1_ps(kHalfPi), two_pi = _mm512_set1_ps(2 * kPi);
  const __m512 e = fast_atan_ratio16(sin_e, cos_e);  // cos_e >= 0
  const __m512 r0 = sqrt16(_mm512_fmadd_ps(nu, nu, _mm512_mul_ps(nc, nc)));
  // phase = atan2(nu, nc).
  const __m512 base_phase = fast_atan_ratio16(nu, _mm512_andnot_ps(sign, nc));
  const __m512 phase =
      _mm512_mask_blend_ps(_mm512_cmp_ps_mask(nc, zero, _CMP_LT_OQ), base_phase,
                           _mm512_sub_ps(_mm512_or_ps(_mm512_and_ps(sign, nu), pi), base_phase));
  const StripNodes& nodes = strip_nodes();
  const float* cos_psi = nodes.cos_psi.data() + nodes.offsets[strips];
  const float* sin_psi = nodes.sin_psi.data() + nodes.offsets[strips];
  __m512 acc = zero;
  for (int j = 0; j < strips; ++j) {
    const __m512 a = chord_a[j], aa = _mm512_mul_ps(a, a);
    const __m512 sn = _mm512_set1_ps(sin_psi[j]);
    const __m512 s = _mm512_mul_ps(rho, _mm512_set1_ps(cos_psi[j]));
    const __m512 h = _mm512_mul_ps(rho, sn);
    const __m512 q = _mm512_fnmadd_ps(s, s, one), r = sqrt16(q);
    const __m512 t_max = fast_atan_ratio16(h, cos_half);
    const __m512 as = fast_atan_ratio16(a, sqrt16(max16(_mm512_sub_ps(q, aa), zero)));
    const __mmask16 partial = _mm512_cmp_ps_mask(a, _mm512_xor_ps(r, sign), _CMP_GT_OQ);
    const __m512 lo = _mm512_mask_blend_ps(partial, _mm512_xor_ps(t_max, sign),
                                           max16(_mm512_xor_ps(t_max, sign), _mm512_sub_ps(as, e)));
    const __m512 hi =
        _mm512_mask_blend_ps(partial, t_max, min16(t_max, _mm512_sub_ps(_mm512_sub_ps(pi, as), e)));
    const __mmask16 ok = static_cast<__mmask16>(~_mm512_cmp_ps_mask(a, r, _CMP_GE_OQ)) &
                         _mm512_cmp_ps_mask(lo, hi, _CMP_LT_OQ);
    // In front of the tangent plane: r0 r cos(t - phase) + ns s > 0.
    const __m512 rr = _mm512_mul_ps(r0, r), nss = _mm512_mul_ps(ns, s);
    const __mmask16 no_plane = _mm512_cmp_ps_mask(rr, zero, _CMP_LE_OQ);
    const __m512 b = _mm512_div_ps(_mm512_xor_ps(nss, sign), max16(rr, _mm512_set1_ps(1e-30f)));
    const __mmask16 whole = (no_plane & _mm512_cmp_ps_mask(nss, zero, _CMP_GT_OQ)) |
                            (~no_plane & _mm512_cmp_ps_mask(b, _mm512_set1_ps(-1.0f), _CMP_LE_OQ));
    const __mmask16 pieces = ~(no_plane | whole) & _mm512_cmp_ps_mask(b, one, _CMP_LT_OQ);
    const __m512 bc = min16(max16(b, _mm512_set1_ps(-1.0f)), one);
    const __m512 width = _mm512_sub_ps(
        half_pi, fast_atan_ratio16(bc, sqrt16(max16(_mm512_fnmadd_ps(bc, bc, one), zero))));
    __m512 part = zero;
    for (int k = -1; k <= 1; ++k) {
      const __m512 centre =
          _mm512_add_ps(phase, _mm512_mul_ps(_mm512_set1_ps(static_cast<float>(k)), two_pi));
      __m512 l = max16(lo, _mm512_sub_ps(centre, width));
      __m512 u = min16(hi, _mm512_add_ps(centre, width));
      __mmask16 use = pieces & _mm512_cmp_ps_mask(l, u, _CMP_LT_OQ);
      if (k == 0) {  // the whole chord takes this slot
        l = _mm512_mask_blend_ps(whole, l, lo);
        u = _mm512_mask_blend_ps(whole, u, hi);
        use |= whole;
      }
      if (use == 0) continue;
      const __m512 m = _mm512_mul_ps(_mm512_add_ps(u, l), _mm512_set1_ps(0.5f));
      const __m512 half = _mm512_mul_ps(_mm512_sub_ps(u, l), _mm512_set1_ps(0.5f));
      const __m512 chord =
          _mm512_fmadd_ps(_mm512_mul_ps(_mm512_add_ps(r, r), fast_sin16(half)),
                          _mm512_fmadd_ps(nc, fast_cos16(m), _mm512_mul_ps(nu, fast_sin16(m))),
                          _mm512_mul_ps(nss, _mm512_sub_ps(u, l)));
      part = _mm512_add_ps(part, _mm512_maskz_mov_ps(use, chord));
    }
    acc = _mm512_fmadd_ps(sn, _mm512_maskz_mov_ps(ok, part), acc);
  }
  return acc;
}

}  // namespace

bool cap_chords16(const CapChordLanes16& in, float radius, int strips, float* e) {
  const int count = std::clamp(in.count, 1, kMaxCapHorizons);
  const __m512 zero = _mm512_setzero_ps();
  Cap16 cap;
  load_cap16(in, radius, cap);
  const __m512 &rho = cap.rho, &nc = cap.nc, &cos_e = cap.cos_e, &sin_e = cap.sin_e;
  const __m512& cos_half = cap.cos_half;
  // Sines of the horizon samples, their lowest and highest.
  const __m512 half_pi = _mm512_set1_ps(kHalfPi);
  __m512 sh[kMaxCapHorizons] = {};
  for (int k = 0; k < count; ++k)
    sh[k] = fast_sin16(
        min16(max16(_mm512_loadu_ps(in.horizon[k]), _mm512_sub_ps(zero, half_pi)), half_pi));
  __m512 lowest = sh[0], highest = sh[0];
  for (int k = 1; k < count; ++k) lowest = min16(lowest, sh[k]), highest = max16(highest, sh[k]);
  const __mmask16 visible = cap.lit & _mm512_cmp_ps_mask(lowest, cap.top, _CMP_LT_OQ);
  const __mmask16 open = _mm512_cmp_ps_mask(highest, cap.bottom, _CMP_LE_OQ);
  const __mmask16 in_front = _mm512_cmp_ps_mask(nc, rho, _CMP_GE_OQ);
  // No cap is wide (`wide` infinite) and nothing is deferred: the caps the tangent plane cuts
  // take general chords; those in front of it the horizon cuts, the lens (one sample).
  const __mmask16 cut = ~in_front & visible;
  const __mmask16 chords = ~cut & ~(open & in_front) & visible;
  const bool lens = count == 1;
  if (!lens && chords != 0) return false;  // front chords: not in this kernel
  __m512 value = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(kPi), _mm512_mul_ps(rho, rho)), nc);
  const __mmask16 any_chords = chords | cut;
  if (any_chords != 0) {
    __m512 ns, nw, nu;
    cap_frame16(cap, ns, nw, nu);
    __m512 lens_value = zero;
    if (lens && chords != 0) {
      const __m512 omega =
          min16(max16(_mm512_loadu_ps(in.horizon[0]), _mm512_sub_ps(zero, half_pi)), half_pi);
      lens_value = front_lens16(rho, cos_half, nc, cap.nz, nw, nu, sin_e, cos_e, omega, sh[0]);
    }
    __m512 sum = zero;
    if (cut != 0) {
      // The horizon along each chord: linear in tau = cos(psi) between the samples; open: -1.
      __m512 chord_a[kMaxStrips];
      const StripNodes& sn = strip_nodes();
      const float* cos_psi = sn.cos_psi.data() + sn.offsets[strips];
      const float* tau = nodes().tau[count].data();
      for (int j = 0; j < strips; ++j) {
        __m512 a = sh[0];
        if (count > 1) {
          const float c = cos_psi[j];
          int k = 0;
          while (k + 2 < count && c > tau[k + 1]) ++k;
          const float w = std::clamp((c - tau[k]) / (tau[k + 1] - tau[k]), 0.0f, 1.0f);
          a = _mm512_fmadd_ps(_mm512_set1_ps(w), _mm512_sub_ps(sh[k + 1], sh[k]), sh[k]);
        }
        chord_a[j] = _mm512_mask_blend_ps(open, a, _mm512_set1_ps(-1.0f));
      }
      sum = _mm512_maskz_mov_ps(
          cut, general_chords16(rho, cos_half, nc, ns, nu, sin_e, cos_e, chord_a, strips));
    }
    const __m512 scaled = max16(
        _mm512_mul_ps(sum, _mm512_mul_ps(rho, _mm512_set1_ps(kPi / static_cast<float>(strips)))),
        zero);
    value = _mm512_mask_blend_ps(any_chords, value, scaled);
    if (lens) value = _mm512_mask_blend_ps(chords, value, lens_value);
  }
  _mm512_storeu_ps(e, _mm512_maskz_mov_ps(visible, value));
  return true;
}

unsigned cap_first_pass16(const CapLanes16& in, float radius, float wide, float* e) {
  const __m512 zero = _mm512_setzero_ps();
  Cap16 cap;
  load_cap16(in, radius, cap);
  const __m512 &rho = cap.rho, &nc = cap.nc, &cos_e = cap.cos_e, &sin_e = cap.sin_e;
  const __m512& cos_half = cap.cos_half;
  // The horizon's sine.
  const __m512 half_pi = _mm512_set1_ps(kHalfPi);
  const __m512 omega =
      min16(max16(_mm512_loadu_ps(in.horizon), _mm512_sub_ps(zero, half_pi)), half_pi);
  const __m512 sin_o = fast_sin16(omega);
  const __mmask16 visible = cap.lit & _mm512_cmp_ps_mask(sin_o, cap.top, _CMP_LT_OQ);
  const __mmask16 open = _mm512_cmp_ps_mask(sin_o, cap.bottom, _CMP_LE_OQ);
  const __mmask16 in_front = _mm512_cmp_ps_mask(nc, rho, _CMP_GE_OQ);
  const __mmask16 is_wide =
      cap.outside & cap.front & _mm512_cmp_ps_mask(rho, _mm512_set1_ps(wide), _CMP_GE_OQ);
  // Handed back: wide caps and caps the tangent plane cuts. The others in front of the plane
  // that the horizon cuts take the lens.
  const __mmask16 cut = ~is_wide & ~in_front & visible;
  const __mmask16 lens = ~(is_wide | cut) & ~(open & in_front) & visible;
  const __mmask16 other = is_wide | cut;
  __m512 value = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(kPi), _mm512_mul_ps(rho, rho)), nc);
  if (lens) {
    __m512 ns, nw, nu;
    cap_frame16(cap, ns, nw, nu);
    value = _mm512_mask_blend_ps(
        lens, value, front_lens16(rho, cos_half, nc, cap.nz, nw, nu, sin_e, cos_e, omega, sin_o));
  }
  _mm512_storeu_ps(e, _mm512_maskz_mov_ps(~other & visible, value));
  return other;
}

}  // namespace penumbra::terrain_shadow::detail::avx512

#include "avx512_target_end.h"
#endif
