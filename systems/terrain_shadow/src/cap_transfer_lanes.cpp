// cap_transfer8: cap_transfer on eight receivers at once, one per AVX2 lane (cap_transfer.h).
#include "penumbra/systems/terrain_shadow/cap_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

#include "cap_chords.h"
#include "fast_math.h"
#include "sweep_lanes.h"

namespace penumbra::terrain_shadow {
namespace {

using detail::kHalfPi;
using detail::kMaxStrips;
using detail::kPi;
using detail::nodes;
using detail::strip_nodes;
using detail::StripNodes;
#ifdef __AVX2__
using detail::chord_bounds8;
using detail::ChordBounds;
#endif

}  // namespace

#ifdef __AVX2__
namespace {

// front_chords on eight receivers (one per lane), each with its own cap and, per chord j, its
// horizon sine chord_a[j] (-1: open); the strips' nodes are shared. Returns the sum over the
// chords per lane.
__m256 front_chords8(__m256 rho, __m256 nc, __m256 ns, __m256 nu, __m256 sin_e, __m256 cos_e,
                     const __m256* chord_a, int strips) {
  const __m256 one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 tiny = _mm256_set1_ps(1e-30f), sign = _mm256_set1_ps(-0.0f);
  const __m256 below = _mm256_cmp_ps(sin_e, zero, _CMP_LT_OQ);
  const __m256 above = _mm256_cmp_ps(sin_e, zero, _CMP_GT_OQ);
  const StripNodes& nodes = strip_nodes();
  const float* cos_psi = nodes.cos_psi.data() + nodes.offsets[strips];
  const float* sin_psi = nodes.sin_psi.data() + nodes.offsets[strips];
  __m256 acc = zero;
  for (int j = 0; j < strips; ++j) {
    const __m256 sn = _mm256_set1_ps(sin_psi[j]);
    const __m256 s = _mm256_mul_ps(rho, _mm256_set1_ps(cos_psi[j]));
    const __m256 h = _mm256_mul_ps(rho, sn);
    const __m256 q = _mm256_fnmadd_ps(s, s, one);
    const ChordBounds cb = chord_bounds8(chord_a[j], q, h, sin_e, cos_e, below, above);
    const __m256 lo = cb.lo, hi = cb.hi, c_lo = cb.c_lo, c_hi = cb.c_hi;
    // asin(hi / sq) - asin(lo / sq) as one angle: atan2(hi c_lo - lo c_hi, c_hi c_lo + hi lo)
    // in [0, pi], and c0(lo) - c0(hi) in product form (tiny caps keep their precision), both
    // from one division.
    const __m256 y = _mm256_max_ps(_mm256_fmsub_ps(hi, c_lo, _mm256_mul_ps(lo, c_hi)), zero);
    const __m256 x = _mm256_fmadd_ps(c_hi, c_lo, _mm256_mul_ps(hi, lo));
    const __m256 ax = _mm256_andnot_ps(sign, x);
    const __m256 big = _mm256_max_ps(_mm256_max_ps(y, ax), tiny);
    const __m256 sum_c = _mm256_max_ps(_mm256_add_ps(c_lo, c_hi), tiny);
    const __m256 inv = _mm256_div_ps(one, _mm256_mul_ps(big, sum_c));
    __m256 as =
        detail::fast_atan_unit8(_mm256_mul_ps(_mm256_mul_ps(_mm256_min_ps(y, ax), sum_c), inv));
    as = _mm256_blendv_ps(as, _mm256_sub_ps(_mm256_set1_ps(kHalfPi), as),
                          _mm256_cmp_ps(y, ax, _CMP_GT_OQ));
    as = _mm256_blendv_ps(as, _mm256_sub_ps(_mm256_set1_ps(kPi), as), x);  // x < 0: obtuse
    const __m256 len = _mm256_sub_ps(hi, lo);
    const __m256 dc =
        _mm256_mul_ps(_mm256_mul_ps(len, _mm256_add_ps(hi, lo)), _mm256_mul_ps(big, inv));
    const __m256 chord =
        _mm256_fmadd_ps(nc, len, _mm256_fmadd_ps(_mm256_mul_ps(ns, s), as, _mm256_mul_ps(nu, dc)));
    acc = _mm256_fmadd_ps(sn, chord, acc);
  }
  return acc;
}

// front_lens on eight receivers (cap_chords.h): caps wholly in front of the tangent plane above
// a constant horizon omega (radians, in [-pi/2, pi/2]) whose sine is sin_o; nw = n.h, nu = n.u_c.
__m256 front_lens8(__m256 rho, __m256 cos_half, __m256 nc, __m256 nz, __m256 nw, __m256 nu,
                   __m256 sin_e, __m256 cos_e, __m256 omega, __m256 sin_o) {
  const __m256 one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps(), half = _mm256_set1_ps(0.5f);
  const __m256 two = _mm256_set1_ps(2.0f), tiny = _mm256_set1_ps(1e-30f);
  const __m256 rho2 = _mm256_mul_ps(rho, rho);
  const __m256 omc = _mm256_div_ps(rho2, _mm256_add_ps(one, cos_half));  // 1 - cos(beta)
  const __m256 cos_o = detail::fast_cos8(omega);
  const __m256 d_sin = _mm256_sub_ps(sin_o, sin_e), d_cos = _mm256_sub_ps(cos_e, cos_o);
  // cos(phi) = (sin_o - cos(beta) sin_e) / (rho cos_e).
  const __m256 cphi =
      _mm256_min_ps(_mm256_max_ps(_mm256_div_ps(_mm256_fmadd_ps(sin_e, omc, d_sin),
                                                _mm256_max_ps(_mm256_mul_ps(rho, cos_e), tiny)),
                                  _mm256_set1_ps(-1.0f)),
                    one);
  const __m256 sphi = _mm256_sqrt_ps(
      _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(one, cphi), _mm256_add_ps(one, cphi)), zero));
  const __m256 phi =
      _mm256_sub_ps(_mm256_set1_ps(kHalfPi), detail::fast_atan_ratio8(cphi, sphi));  // acos
  // 1 - cos(psi) = (cos(omega - e) - cos(beta)) / (cos_o cos_e), cos(omega - e) = 1 - (d_sin^2
  // + d_cos^2) / 2.
  const __m256 chord2 = _mm256_fmadd_ps(d_sin, d_sin, _mm256_mul_ps(d_cos, d_cos));
  const __m256 k =
      _mm256_min_ps(_mm256_max_ps(_mm256_div_ps(_mm256_fnmadd_ps(half, chord2, omc),
                                                _mm256_max_ps(_mm256_mul_ps(cos_o, cos_e), tiny)),
                                  zero),
                    two);
  const __m256 hk = _mm256_mul_ps(half, k);
  const __m256 psi = _mm256_mul_ps(
      two, detail::fast_atan_ratio8(_mm256_sqrt_ps(hk), _mm256_sqrt_ps(_mm256_sub_ps(one, hk))));
  const __m256 spsi = _mm256_sqrt_ps(_mm256_mul_ps(k, _mm256_sub_ps(two, k)));
  // n.(t_h - u_c) + (1 - cos b) nu.
  const __m256 ends =
      _mm256_fnmadd_ps(d_cos, nz, _mm256_fnmadd_ps(d_sin, nw, _mm256_mul_ps(omc, nu)));
  const __m256 arcs =
      _mm256_fmadd_ps(_mm256_mul_ps(_mm256_sub_ps(psi, spsi), _mm256_mul_ps(cos_o, cos_o)), nz,
                      _mm256_mul_ps(_mm256_mul_ps(phi, rho2), nc));
  return _mm256_max_ps(_mm256_fmadd_ps(_mm256_mul_ps(rho, sphi), ends, arcs), zero);
}

// general_chords on eight receivers (caps the tangent plane cuts): chords in t, bounded by the
// horizon and by the tangent plane's sinusoid, up to three pieces a chord (the plane's interval
// and its two 2 pi images), each sq (nc sin t - nu cos t) + ns s t integrated in closed form.
__m256 general_chords8(__m256 rho, __m256 cos_half, __m256 nc, __m256 ns, __m256 nu, __m256 sin_e,
                       __m256 cos_e, const __m256* chord_a, int strips) {
  const __m256 one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 sign = _mm256_set1_ps(-0.0f), pi = _mm256_set1_ps(kPi);
  const __m256 half_pi = _mm256_set1_ps(kHalfPi), two_pi = _mm256_set1_ps(2 * kPi);
  const __m256 e = detail::fast_atan_ratio8(sin_e, cos_e);  // cos_e >= 0
  const __m256 r0 = _mm256_sqrt_ps(_mm256_fmadd_ps(nu, nu, _mm256_mul_ps(nc, nc)));
  // phase = atan2(nu, nc).
  const __m256 base_phase = detail::fast_atan_ratio8(nu, _mm256_andnot_ps(sign, nc));
  const __m256 phase = _mm256_blendv_ps(
      base_phase, _mm256_sub_ps(_mm256_or_ps(_mm256_and_ps(sign, nu), pi), base_phase),
      _mm256_cmp_ps(nc, zero, _CMP_LT_OQ));
  const StripNodes& nodes = strip_nodes();
  const float* cos_psi = nodes.cos_psi.data() + nodes.offsets[strips];
  const float* sin_psi = nodes.sin_psi.data() + nodes.offsets[strips];
  __m256 acc = zero;
  for (int j = 0; j < strips; ++j) {
    const __m256 a = chord_a[j], aa = _mm256_mul_ps(a, a);
    const __m256 sn = _mm256_set1_ps(sin_psi[j]);
    const __m256 s = _mm256_mul_ps(rho, _mm256_set1_ps(cos_psi[j]));
    const __m256 h = _mm256_mul_ps(rho, sn);
    const __m256 q = _mm256_fnmadd_ps(s, s, one), r = _mm256_sqrt_ps(q);
    // t_max = asin(h / r) = atan(h / cos_half), since r^2 - h^2 = 1 - rho^2.
    const __m256 t_max = detail::fast_atan_ratio8(h, cos_half);
    // Above the horizon: sin(e + t) > a / r, i.e. e + t in (asin(a / r), pi - asin(a / r)).
    const __m256 as =
        detail::fast_atan_ratio8(a, _mm256_sqrt_ps(_mm256_max_ps(_mm256_sub_ps(q, aa), zero)));
    const __m256 partial = _mm256_cmp_ps(a, _mm256_xor_ps(r, sign), _CMP_GT_OQ);
    const __m256 lo =
        _mm256_blendv_ps(_mm256_xor_ps(t_max, sign),
                         _mm256_max_ps(_mm256_xor_ps(t_max, sign), _mm256_sub_ps(as, e)), partial);
    const __m256 hi = _mm256_blendv_ps(
        t_max, _mm256_min_ps(t_max, _mm256_sub_ps(_mm256_sub_ps(pi, as), e)), partial);
    const __m256 ok =
        _mm256_andnot_ps(_mm256_cmp_ps(a, r, _CMP_GE_OQ), _mm256_cmp_ps(lo, hi, _CMP_LT_OQ));
    // In front of the tangent plane: r0 r cos(t - phase) + ns s > 0.
    const __m256 rr = _mm256_mul_ps(r0, r), nss = _mm256_mul_ps(ns, s);
    const __m256 no_plane = _mm256_cmp_ps(rr, zero, _CMP_LE_OQ);
    const __m256 b =
        _mm256_div_ps(_mm256_xor_ps(nss, sign), _mm256_max_ps(rr, _mm256_set1_ps(1e-30f)));
    const __m256 whole = _mm256_or_ps(
        _mm256_and_ps(no_plane, _mm256_cmp_ps(nss, zero, _CMP_GT_OQ)),
        _mm256_andnot_ps(no_plane, _mm256_cmp_ps(b, _mm256_set1_ps(-1.0f), _CMP_LE_OQ)));
    const __m256 pieces =
        _mm256_andnot_ps(_mm256_or_ps(no_plane, whole), _mm256_cmp_ps(b, one, _CMP_LT_OQ));
    // width = acos(b) = pi / 2 - asin(b).
    const __m256 bc = _mm256_min_ps(_mm256_max_ps(b, _mm256_set1_ps(-1.0f)), one);
    const __m256 width = _mm256_sub_ps(
        half_pi, detail::fast_atan_ratio8(
                     bc, _mm256_sqrt_ps(_mm256_max_ps(_mm256_fnmadd_ps(bc, bc, one), zero))));
    __m256 part = zero;
    for (int k = -1; k <= 1; ++k) {
      const __m256 centre =
          _mm256_add_ps(phase, _mm256_mul_ps(_mm256_set1_ps(static_cast<float>(k)), two_pi));
      __m256 l = _mm256_max_ps(lo, _mm256_sub_ps(centre, width));
      __m256 u = _mm256_min_ps(hi, _mm256_add_ps(centre, width));
      __m256 use = _mm256_and_ps(pieces, _mm256_cmp_ps(l, u, _CMP_LT_OQ));
      if (k == 0) {  // the whole chord takes this slot
        l = _mm256_blendv_ps(l, lo, whole);
        u = _mm256_blendv_ps(u, hi, whole);
        use = _mm256_or_ps(use, whole);
      }
      if (_mm256_testz_ps(use, use)) continue;
      const __m256 m = _mm256_mul_ps(_mm256_add_ps(u, l), _mm256_set1_ps(0.5f));
      const __m256 half = _mm256_mul_ps(_mm256_sub_ps(u, l), _mm256_set1_ps(0.5f));
      const __m256 chord = _mm256_fmadd_ps(
          _mm256_mul_ps(_mm256_add_ps(r, r), detail::fast_sin8(half)),
          _mm256_fmadd_ps(nc, detail::fast_cos8(m), _mm256_mul_ps(nu, detail::fast_sin8(m))),
          _mm256_mul_ps(nss, _mm256_sub_ps(u, l)));
      part = _mm256_add_ps(part, _mm256_and_ps(use, chord));
    }
    acc = _mm256_fmadd_ps(sn, _mm256_and_ps(ok, part), acc);
  }
  return acc;
}

}  // namespace
#endif

#ifdef __AVX2__
namespace {

// cap_transfer8's lanes. kFirstPass: one horizon sample and chords deferred (a light's pass over
// every texel), compiled without the strips.
template <bool kFirstPass>
unsigned cap_lanes8(const CapLanes& in, float radius, float wide, int strips, bool defer_chords,
                    int count, float* e) {
  const __m256 dx = _mm256_loadu_ps(in.dx), dy = _mm256_loadu_ps(in.dy),
               dz = _mm256_loadu_ps(in.dz);
  const __m256 nx = _mm256_loadu_ps(in.nx), ny = _mm256_loadu_ps(in.ny),
               nz = _mm256_loadu_ps(in.nz);
  const __m256 r = _mm256_set1_ps(radius), one = _mm256_set1_ps(1.0f);
  const __m256 zero = _mm256_setzero_ps();
  // make_light_cap in lanes.
  const __m256 plane2 = _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx));
  const __m256 dist = _mm256_sqrt_ps(_mm256_fmadd_ps(dz, dz, plane2));
  const __m256 outside = _mm256_cmp_ps(dist, r, _CMP_GT_OQ);
  const __m256 inv = _mm256_div_ps(one, dist);
  const __m256 nd = _mm256_fmadd_ps(nz, dz, _mm256_fmadd_ps(ny, dy, _mm256_mul_ps(nx, dx)));
  const __m256 front = _mm256_cmp_ps(nd, _mm256_sub_ps(zero, r), _CMP_GT_OQ);
  const __m256 rho = _mm256_mul_ps(r, inv), nc = _mm256_mul_ps(nd, inv);
  const __m256 plane = _mm256_sqrt_ps(plane2);
  const __m256 cos_e = _mm256_mul_ps(plane, inv), sin_e = _mm256_mul_ps(dz, inv);
  const __m256 cos_half = _mm256_mul_ps(
      _mm256_sqrt_ps(_mm256_mul_ps(_mm256_sub_ps(dist, r), _mm256_add_ps(dist, r))), inv);
  // Sines of the horizon samples (fast_sin's polynomial, clamped to [-pi/2, pi/2]), their
  // lowest and highest.
  __m256 sh[kMaxCapHorizons] = {};  // the first count (>= 1) set below
  const __m256 half_pi = _mm256_set1_ps(kHalfPi);
  for (int k = 0; k < count; ++k) {
    sh[k] = detail::fast_sin8(_mm256_min_ps(
        _mm256_max_ps(_mm256_loadu_ps(in.horizon[k]), _mm256_sub_ps(zero, half_pi)), half_pi));
  }
  __m256 lowest = sh[0], highest = sh[0];
  for (int k = 1; k < count; ++k) {
    lowest = _mm256_min_ps(lowest, sh[k]);
    highest = _mm256_max_ps(highest, sh[k]);
  }
  // The cap's lowest and highest elevation (sines), as cap_transfer.
  const __m256 pole = _mm256_cmp_ps(rho, cos_e, _CMP_GT_OQ);
  const __m256 bottom = _mm256_blendv_ps(
      _mm256_fmsub_ps(sin_e, cos_half, _mm256_mul_ps(cos_e, rho)), _mm256_set1_ps(-1.0f),
      _mm256_and_ps(pole, _mm256_cmp_ps(sin_e, zero, _CMP_LT_OQ)));
  const __m256 top =
      _mm256_blendv_ps(_mm256_fmadd_ps(sin_e, cos_half, _mm256_mul_ps(cos_e, rho)), one,
                       _mm256_and_ps(pole, _mm256_cmp_ps(sin_e, zero, _CMP_GT_OQ)));
  const __m256 lit = _mm256_and_ps(_mm256_and_ps(outside, front),
                                   _mm256_cmp_ps(nc, _mm256_sub_ps(zero, rho), _CMP_GT_OQ));
  const __m256 visible = _mm256_and_ps(lit, _mm256_cmp_ps(lowest, top, _CMP_LT_OQ));
  const __m256 open = _mm256_cmp_ps(highest, bottom, _CMP_LE_OQ);
  const __m256 in_front = _mm256_cmp_ps(nc, rho, _CMP_GE_OQ);
  const __m256 is_wide = _mm256_and_ps(_mm256_and_ps(outside, front),
                                       _mm256_cmp_ps(rho, _mm256_set1_ps(wide), _CMP_GE_OQ));
  // Chords: caps in front of the tangent plane the horizon cuts (front_chords8) and caps the
  // tangent plane cuts (general_chords8); wide caps are left to the caller.
  const __m256 cut = _mm256_andnot_ps(is_wide, _mm256_andnot_ps(in_front, visible));
  const __m256 whole = _mm256_and_ps(open, in_front);
  const __m256 front_chords =
      _mm256_andnot_ps(_mm256_or_ps(is_wide, cut), _mm256_andnot_ps(whole, visible));
  // Deferred: the lanes whose strips cost as much for one lane as for eight; a constant
  // horizon's front caps are a closed form (front_lens8), computed here.
  const bool lens = kFirstPass || count == 1;
  const bool defer = kFirstPass || defer_chords;
  const __m256 strips_needed = lens ? cut : _mm256_or_ps(front_chords, cut);
  const __m256 other = defer ? _mm256_or_ps(is_wide, strips_needed) : is_wide;
  const __m256 chords = defer && !lens ? zero : front_chords;
  const __m256 cut_chords = defer ? zero : cut;
  __m256 value = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(kPi), _mm256_mul_ps(rho, rho)), nc);
  const __m256 any_chords = _mm256_or_ps(chords, cut_chords);
  if (!_mm256_testz_ps(any_chords, any_chords)) {
    // The cap's frame (cap_transfer): side = (-pd.y, pd.x, 0), up = (-sin_e pd, cos_e).
    const __m256 has_plane = _mm256_cmp_ps(plane, zero, _CMP_GT_OQ);
    const __m256 inv_plane = _mm256_div_ps(one, _mm256_max_ps(plane, _mm256_set1_ps(1e-30f)));
    const __m256 pdx = _mm256_blendv_ps(one, _mm256_mul_ps(dx, inv_plane), has_plane);
    const __m256 pdy = _mm256_and_ps(has_plane, _mm256_mul_ps(dy, inv_plane));
    const __m256 ns = _mm256_fmsub_ps(ny, pdx, _mm256_mul_ps(nx, pdy));
    const __m256 nw = _mm256_fmadd_ps(ny, pdy, _mm256_mul_ps(nx, pdx));
    const __m256 nu = _mm256_fmsub_ps(nz, cos_e, _mm256_mul_ps(sin_e, nw));
    __m256 lens_value = zero;
    if (lens && !_mm256_testz_ps(chords, chords)) {
      const __m256 omega = _mm256_min_ps(
          _mm256_max_ps(_mm256_loadu_ps(in.horizon[0]), _mm256_sub_ps(zero, half_pi)), half_pi);
      lens_value = front_lens8(rho, cos_half, nc, nz, nw, nu, sin_e, cos_e, omega, sh[0]);
    }
    // The horizon along each chord: linear in tau = cos(psi) between the samples, as
    // cap_transfer (the weights depend on the chord only); open: -1.
    __m256 chord_a[kMaxStrips];
    const StripNodes& sn = strip_nodes();
    const float* cos_psi = sn.cos_psi.data() + sn.offsets[strips];
    const float* tau = nodes().tau[count].data();
    const __m256 minus_one = _mm256_set1_ps(-1.0f);
    const bool any_strips = !kFirstPass && (!lens || !_mm256_testz_ps(cut_chords, cut_chords));
    for (int j = 0; j < (any_strips ? strips : 0); ++j) {
      __m256 a = sh[0];
      if (count > 1) {
        const float c = cos_psi[j];
        int k = 0;
        while (k + 2 < count && c > tau[k + 1]) ++k;
        const float w = std::clamp((c - tau[k]) / (tau[k + 1] - tau[k]), 0.0f, 1.0f);
        a = _mm256_fmadd_ps(_mm256_set1_ps(w), _mm256_sub_ps(sh[k + 1], sh[k]), sh[k]);
      }
      chord_a[j] = _mm256_blendv_ps(a, minus_one, open);
    }
    __m256 sum = zero;
    if (!kFirstPass && !lens && !_mm256_testz_ps(chords, chords))
      sum = front_chords8(rho, nc, ns, nu, sin_e, cos_e, chord_a, strips);
    if (!kFirstPass && !_mm256_testz_ps(cut_chords, cut_chords))
      sum = _mm256_blendv_ps(
          sum, general_chords8(rho, cos_half, nc, ns, nu, sin_e, cos_e, chord_a, strips),
          cut_chords);
    const __m256 scaled = _mm256_max_ps(
        _mm256_mul_ps(sum, _mm256_mul_ps(rho, _mm256_set1_ps(kPi / static_cast<float>(strips)))),
        zero);
    value = _mm256_blendv_ps(value, scaled, any_chords);
    if (lens) value = _mm256_blendv_ps(value, lens_value, chords);
  }
  _mm256_storeu_ps(e, _mm256_and_ps(_mm256_andnot_ps(other, visible), value));
  return static_cast<unsigned>(_mm256_movemask_ps(other));
}

}  // namespace
#endif

unsigned cap_transfer8(const CapLanes& in, float radius, float wide, int strips, bool defer_chords,
                       float* e) {
  strips = std::clamp(strips, 1, kMaxStrips);
  const int count = std::clamp(in.count, 1, kMaxCapHorizons);
#ifdef __AVX2__
  return count == 1 && defer_chords
             ? cap_lanes8<true>(in, radius, wide, strips, true, 1, e)
             : cap_lanes8<false>(in, radius, wide, strips, defer_chords, count, e);
#else
  unsigned other = 0;
  for (int l = 0; l < 8; ++l) {
    e[l] = 0;
    const glm::vec3 d(in.dx[l], in.dy[l], in.dz[l]), n(in.nx[l], in.ny[l], in.nz[l]);
    LightCap cap;
    if (glm::dot(d, n) <= -radius || !make_light_cap(d, radius, cap)) continue;
    if (cap.rho >= wide || defer_chords) {  // deferred: every lit lane, closed or not
      other |= 1u << l;
    } else {
      float horizon[kMaxCapHorizons];
      for (int k = 0; k < count; ++k) horizon[k] = in.horizon[k][l];
      e[l] = cap_transfer(cap, n, horizon, count, strips);
    }
  }
  return other;
#endif
}

#ifdef __AVX2__
namespace detail::avx512 {  // cap_transfer_lanes_avx512.cpp
unsigned cap_first_pass16(const CapLanes16& in, float radius, float wide, float* e);
// cap_chords16's kernel; false (e untouched) where a lane needs front chords.
bool cap_chords16(const CapChordLanes16& in, float radius, int strips, float* e);
}  // namespace detail::avx512
#endif

namespace {
// Receivers o .. o + 7 of sixteen (CapLanes16 or CapChordLanes16) as eight lanes, horizons not set.
template <class Lanes16>
CapLanes receivers_of(const Lanes16& in, int o) {
  CapLanes lanes;
  std::copy_n(in.dx + o, 8, lanes.dx), std::copy_n(in.dy + o, 8, lanes.dy);
  std::copy_n(in.dz + o, 8, lanes.dz), std::copy_n(in.nx + o, 8, lanes.nx);
  std::copy_n(in.ny + o, 8, lanes.ny), std::copy_n(in.nz + o, 8, lanes.nz);
  return lanes;
}
}  // namespace

unsigned cap_first_pass16(const CapLanes16& in, float radius, float wide, float* e) {
#ifdef __AVX2__
  if (detail::sweep_isa() == detail::SweepIsa::kAvx512)
    return detail::avx512::cap_first_pass16(in, radius, wide, e);
#endif
  unsigned other = 0;
  for (int half = 0; half < 2; ++half) {
    const int o = 8 * half;
    CapLanes lanes = receivers_of(in, o);
    std::copy_n(in.horizon + o, 8, lanes.horizon[0]);
    lanes.count = 1;  // the first pass: the strips are not used
    other |= cap_transfer8(lanes, radius, wide, 1, true, e + o) << o;
  }
  return other;
}

void cap_chords16(const CapChordLanes16& in, float radius, int strips, float* e) {
  strips = std::clamp(strips, 1, kMaxStrips);
#ifdef __AVX2__
  if (detail::sweep_isa() == detail::SweepIsa::kAvx512 &&
      detail::avx512::cap_chords16(in, radius, strips, e))
    return;
#endif
  const float infinite = std::numeric_limits<float>::infinity();
  for (int half = 0; half < 2; ++half) {
    const int o = 8 * half;
    CapLanes lanes = receivers_of(in, o);
    for (int k = 0; k < kMaxCapHorizons; ++k) std::copy_n(in.horizon[k] + o, 8, lanes.horizon[k]);
    lanes.count = in.count;
    cap_transfer8(lanes, radius, infinite, strips, false, e + o);
  }
}

}  // namespace penumbra::terrain_shadow
