// One group of RadialHorizonSweep's lines, scalar and on AVX2 lanes (radial_sweep_lanes.h): the
// upper-hull sweep of [Timonen10] along lines radiating from the light's foot ([Meier13] eq. 4.22).
// Compiled twice, as sweep_lanes.cpp: here for the x86-64-v3 baseline (the scalar kernel, the
// AVX2 lanes, the run-time choice), and by radial_sweep_lanes_avx512.cpp for AVX-512
// (PENUMBRA_RADIAL_LANES_AVX512: the lanes' kernel only, in namespace avx512).
#include "radial_sweep_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#ifdef __AVX2__
#include <immintrin.h>

#include "sweep_lanes.h"  // sweep_isa()
#endif

namespace penumbra::terrain_shadow::detail {
namespace {

constexpr int L = kRadialLanes;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kMinusInf = -std::numeric_limits<float>::infinity();

// The lanes' swept columns: [lo, hi) covers every lane's [first, end) (lo = hi: none).
[[gnu::always_inline]] inline void swept_columns(const RadialGroup& g, int& lo, int& hi) {
  lo = g.width;
  hi = 0;
  for (int l = 0; l < L; ++l)
    if (g.first[l] < g.end[l]) {
      lo = std::min(lo, g.first[l]);
      hi = std::max(hi, g.end[l]);
    }
  if (lo >= hi) lo = hi = 0;
}

[[gnu::always_inline]] inline void fill_nan(float* block, int k0, int k1) {
  if (k1 > k0) std::fill(block + static_cast<std::ptrdiff_t>(k0) * L, block + k1 * L, kNaN);
}

}  // namespace

#ifndef PENUMBRA_RADIAL_LANES_AVX512
void sweep_radial_group_scalar(const RadialGroup& g, RadialScratch& sc, float* block) {
  int lo, hi;
  swept_columns(g, lo, hi);
  sc.hull_r.resize(static_cast<std::size_t>(std::max(hi - lo, 1)));
  sc.hull_h.resize(sc.hull_r.size());
  fill_nan(block, 0, g.width);
  for (int l = 0; l < L; ++l) {
    float* hr = sc.hull_r.data();
    float* hh = sc.hull_h.data();
    int n = 0;
    for (int k = g.first[l]; k < g.end[l]; ++k) {
      const double r = g.r_near + k;
      const double v = g.v0 + r * g.m[l];
      int vi = static_cast<int>(std::floor(v));
      float fv = static_cast<float>(v - vi);
      if (fv > 1 - 1e-5f) {
        ++vi;
        fv = 0;
      }
      if (vi < 0 || vi >= g.size_v - 1) {  // on the border line (within 1e-5)
        vi = std::clamp(vi, 0, g.size_v - 1);
        fv = 0;
      }
      const float* sample = g.heights +
                            static_cast<std::ptrdiff_t>(g.u_first + g.sign * k) * g.stride_u +
                            static_cast<std::ptrdiff_t>(vi) * g.stride_v;
      const float h =
          g.height_scale * (sample[0] + fv * (sample[fv > 0 ? g.stride_v : 0] - sample[0]));
      const float rf = static_cast<float>(r);
      // The tangent from (r, h) to the upper hull of the samples between it and F.
      while (n >= 2 && (hh[n - 1] - h) * (rf - hr[n - 2]) <= (hh[n - 2] - h) * (rf - hr[n - 1]))
        --n;
      block[k * L + l] = n > 0 ? (hh[n - 1] - h) / (rf - hr[n - 1]) * g.inv_metres[l] : kMinusInf;
      hr[n] = rf;
      hh[n] = h;
      ++n;
    }
  }
}

#endif

#ifdef __AVX2__
#ifdef PENUMBRA_RADIAL_LANES_AVX512
namespace avx512 {
#else
namespace avx2 {
#endif

void sweep_radial_group(const RadialGroup& g, RadialScratch& sc, float* block) {
  int lo, hi;
  swept_columns(g, lo, hi);
  fill_nan(block, 0, lo);
  fill_nan(block, hi, g.width);
  if (lo >= hi) return;
  // The hull as links through the steps, as sweep_lanes.cpp: step k's slot (k - lo) * L + l
  // holds the point that was on top of lane l's hull when step k pushed its sample, so a push
  // is one vector store and a pop reads the new third point from the old one's slot (found
  // from its r: r = r_near + k, to a float's precision, far less than a step).
  const std::size_t slots = static_cast<std::size_t>(hi - lo + 1) * L;
  // (The AVX-512 copy keeps (h, r) pairs in hull_h: twice the floats. Each size on its own: the
  // scalar kernel may have sized both alike.)
  if (sc.hull_r.size() < slots) sc.hull_r.resize(slots);
  if (sc.hull_h.size() < 2 * slots) sc.hull_h.resize(2 * slots);
  float* link_h = sc.hull_h.data();

  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256d v0 = _mm256_set1_pd(g.v0), m_lo = _mm256_loadu_pd(g.m.data()),
                m_hi = _mm256_loadu_pd(g.m.data() + 4);
  const __m256i first = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(g.first.data()));
  const __m256i end = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(g.end.data()));
  const __m256 inv_metres = _mm256_loadu_ps(g.inv_metres.data());
  const __m256 scale = _mm256_set1_ps(g.height_scale), almost_one = _mm256_set1_ps(1 - 1e-5f);
  const __m256 nan = _mm256_set1_ps(kNaN), minus_inf = _mm256_set1_ps(kMinusInf);
  const __m256 zero = _mm256_setzero_ps();
  const __m256i izero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1);
  const __m256i v_last = _mm256_set1_epi32(g.size_v - 1), stride_v = _mm256_set1_epi32(g.stride_v);
  const __m256 r_first = _mm256_set1_ps(static_cast<float>(g.r_near + lo));
  const __m256i last_slot = _mm256_set1_epi32(hi - lo);

  // Hull size per lane and its top three points in registers (a = top - 1, b = top - 2,
  // c = top - 3), as sweep_lanes.cpp: a pop needs a and b only. Absent points: r = 0, read
  // from a clamped slot and never used (`top` guards every use).
  // The samples first, all columns (no dependency between them, so the gathers pipeline), then
  // the hull walk over them: its pops are a latency chain, and a short loop body refills faster
  // after the pop loop's exits mispredict.
  const std::size_t columns = static_cast<std::size_t>(hi - lo) * L;
  if (sc.h.size() < columns) sc.h.resize(columns), sc.active.resize(columns);
  for (int k = lo; k < hi; ++k) {
    const double r = g.r_near + k;
    const __m256d rd = _mm256_set1_pd(r);
    const __m256d va = _mm256_add_pd(v0, _mm256_mul_pd(rd, m_lo));
    const __m256d vb = _mm256_add_pd(v0, _mm256_mul_pd(rd, m_hi));
    const __m256d fa = _mm256_floor_pd(va), fb = _mm256_floor_pd(vb);
    __m256i vi = _mm256_setr_m128i(_mm256_cvttpd_epi32(fa), _mm256_cvttpd_epi32(fb));
    __m256 fv = _mm256_setr_m128(_mm256_cvtpd_ps(_mm256_sub_pd(va, fa)),
                                 _mm256_cvtpd_ps(_mm256_sub_pd(vb, fb)));
    const __m256 bump = _mm256_cmp_ps(fv, almost_one, _CMP_GT_OQ);
    vi = _mm256_sub_epi32(vi, _mm256_castps_si256(bump));  // +1 where bumped
    fv = _mm256_andnot_ps(bump, fv);
    const __m256i border =
        _mm256_or_si256(_mm256_cmpgt_epi32(izero, vi),
                        _mm256_cmpgt_epi32(vi, _mm256_sub_epi32(v_last, one)));  // vi >= last
    vi = _mm256_min_epi32(_mm256_max_epi32(vi, izero), v_last);
    fv = _mm256_andnot_ps(_mm256_castsi256_ps(border), fv);
    const __m256i kv = _mm256_set1_epi32(k);
    const __m256 active = _mm256_castsi256_ps(_mm256_andnot_si256(
        _mm256_cmpgt_epi32(first, kv), _mm256_cmpgt_epi32(end, kv)));  // first <= k < end

    const __m256i i0 = _mm256_add_epi32(_mm256_set1_epi32((g.u_first + g.sign * k) * g.stride_u),
                                        _mm256_mullo_epi32(vi, stride_v));
    const __m256i i1 = _mm256_add_epi32(
        i0, _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps(fv, zero, _CMP_GT_OQ)), stride_v));
    __m256 s0, s1;
#ifdef PENUMBRA_RADIAL_LANES_AVX512
    if (g.stride_v == 1 && g.size_v >= 2) {
      // A lane's two samples side by side: one 64-bit gather element, taken one sample earlier
      // on the minor axis's last sample (its right neighbour lies past the row; fv = 0 there).
      const __mmask8 last = _mm256_cmpeq_epi32_mask(vi, v_last);
      const __m512i pair = _mm512_mask_i32gather_epi64(
          _mm512_setzero_si512(), 0xff, _mm256_mask_sub_epi32(i0, last, i0, one), g.heights, 4);
      const __m256 left = _mm256_castsi256_ps(_mm512_maskz_cvtepi64_epi32(0xff, pair));
      const __m256 right = _mm256_castsi256_ps(
          _mm512_maskz_cvtepi64_epi32(0xff, _mm512_maskz_srli_epi64(0xff, pair, 32)));
      s0 = _mm256_mask_blend_ps(last, left, right);
      s1 = _mm256_mask_blend_ps(_mm256_cmp_ps_mask(fv, zero, _CMP_GT_OQ), s0, right);
    } else
#endif
    {
      s0 = _mm256_i32gather_ps(g.heights, i0, 4);
      s1 = _mm256_i32gather_ps(g.heights, i1, 4);
    }
    const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(k - lo) * L;
    _mm256_storeu_ps(
        sc.h.data() + at,
        _mm256_mul_ps(scale, _mm256_add_ps(s0, _mm256_mul_ps(fv, _mm256_sub_ps(s1, s0)))));
    _mm256_storeu_ps(sc.active.data() + at, active);
  }

#ifdef PENUMBRA_RADIAL_LANES_AVX512
  // The same walk with mask registers, a fourth hull point (d) in registers and per lane how
  // many of a, b, c, d are current (c is refilled from the links only when a pop leaves it
  // stale), and each link's (h, r) side by side, one 64-bit gather element: sweep_lanes.cpp's
  // walk16 on eight lanes. The same floats.
  float* links = link_h;  // (h, r) pairs: slot * L + l at links + 2 (slot * L + l)
  const __m256i two = _mm256_set1_epi32(2), three = _mm256_set1_epi32(3),
                four = _mm256_set1_epi32(4);
  const __m512i pairs = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
  __m256i top = izero, depth = izero;
  __m256 ah = zero, ar = zero, bh = zero, br = zero, ch = zero, cr = zero, dh = zero, dr = zero;
  for (int k = lo; k < hi; ++k) {
    const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(k - lo) * L;
    const __m256 rf = _mm256_set1_ps(static_cast<float>(g.r_near + k));
    const __m256 h = _mm256_loadu_ps(sc.h.data() + at);
    const __mmask8 active =
        _mm256_movepi32_mask(_mm256_castps_si256(_mm256_loadu_ps(sc.active.data() + at)));
    for (;;) {
      const __mmask8 can = _mm256_mask_cmpgt_epi32_mask(active, top, one);
      const __m256 lhs = _mm256_mul_ps(_mm256_sub_ps(ah, h), _mm256_sub_ps(rf, br));
      const __m256 rhs = _mm256_mul_ps(_mm256_sub_ps(bh, h), _mm256_sub_ps(rf, ar));
      const __mmask8 pop = _mm256_mask_cmp_ps_mask(can, lhs, rhs, _CMP_LE_OQ);
      if (pop == 0) break;
      top = _mm256_mask_sub_epi32(top, pop, top, one);
      depth = _mm256_mask_sub_epi32(depth, pop, depth, one);
      ah = _mm256_mask_mov_ps(ah, pop, bh), ar = _mm256_mask_mov_ps(ar, pop, br);
      bh = _mm256_mask_mov_ps(bh, pop, ch), br = _mm256_mask_mov_ps(br, pop, cr);
      ch = _mm256_mask_mov_ps(ch, pop, dh), cr = _mm256_mask_mov_ps(cr, pop, dr);
      // Lanes whose c is now stale with a point below b: c from b's link.
      const __mmask8 refill =
          _mm256_mask_cmpgt_epi32_mask(_mm256_mask_cmpgt_epi32_mask(pop, three, depth), top, two);
      if (refill == 0) continue;
      const __m256i b_slot = _mm256_min_epi32(
          _mm256_max_epi32(_mm256_cvtps_epi32(_mm256_sub_ps(br, r_first)), izero), last_slot);
      const __m256i i3 = _mm256_add_epi32(_mm256_slli_epi32(b_slot, 3), lane);
      const __m512i pair =
          _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), refill, i3, links, 8);
      // (GCC 12 warns on the unmasked forms of these two: the zero-masked ones with every lane
      // are the same instructions, as in sweep_lanes.cpp.)
      const __m512i r_bits = _mm512_maskz_srli_epi64(0xff, pair, 32);
      ch = _mm256_mask_mov_ps(ch, refill,
                              _mm256_castsi256_ps(_mm512_maskz_cvtepi64_epi32(0xff, pair)));
      cr = _mm256_mask_mov_ps(cr, refill,
                              _mm256_castsi256_ps(_mm512_maskz_cvtepi64_epi32(0xff, r_bits)));
      depth = _mm256_mask_mov_epi32(depth, refill, three);
    }
    const __mmask8 has = _mm256_cmpgt_epi32_mask(top, izero);
    const __m256 slope =
        _mm256_mul_ps(_mm256_div_ps(_mm256_sub_ps(ah, h), _mm256_sub_ps(rf, ar)), inv_metres);
    _mm256_storeu_ps(
        block + static_cast<std::ptrdiff_t>(k) * L,
        _mm256_mask_blend_ps(active, nan, _mm256_mask_blend_ps(has, minus_inf, slope)));
    // Push on the active lanes: slot k - lo keeps the old top (every lane stores).
    _mm512_storeu_ps(links + 2 * at, _mm512_permutex2var_ps(_mm512_castps256_ps512(ah), pairs,
                                                            _mm512_castps256_ps512(ar)));
    if (active == 0xff) {  // every lane (most columns): register moves, no blends
      top = _mm256_add_epi32(top, one);
      depth = _mm256_min_epi32(_mm256_add_epi32(depth, one), four);
      dh = ch, dr = cr, ch = bh, cr = br, bh = ah, br = ar, ah = h, ar = rf;
      continue;
    }
    top = _mm256_mask_add_epi32(top, active, top, one);
    depth = _mm256_mask_min_epi32(depth, active, _mm256_add_epi32(depth, one), four);
    dh = _mm256_mask_mov_ps(dh, active, ch), dr = _mm256_mask_mov_ps(dr, active, cr);
    ch = _mm256_mask_mov_ps(ch, active, bh), cr = _mm256_mask_mov_ps(cr, active, br);
    bh = _mm256_mask_mov_ps(bh, active, ah), br = _mm256_mask_mov_ps(br, active, ar);
    ah = _mm256_mask_mov_ps(ah, active, h), ar = _mm256_mask_mov_ps(ar, active, rf);
  }
#else
  float* link_r = sc.hull_r.data();
  __m256i top = izero;
  __m256 ah = zero, ar = zero, bh = zero, br = zero, ch = zero, cr = zero;
  for (int k = lo; k < hi; ++k) {
    const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(k - lo) * L;
    const __m256 rf = _mm256_set1_ps(static_cast<float>(g.r_near + k));
    const __m256 h = _mm256_loadu_ps(sc.h.data() + at);
    const __m256 active = _mm256_loadu_ps(sc.active.data() + at);

    // Pop while the top is not above the line from the second point (the scalar test).
    for (;;) {
      const __m256 can = _mm256_and_ps(active, _mm256_castsi256_ps(_mm256_cmpgt_epi32(top, one)));
      const __m256 lhs = _mm256_mul_ps(_mm256_sub_ps(ah, h), _mm256_sub_ps(rf, br));
      const __m256 rhs = _mm256_mul_ps(_mm256_sub_ps(bh, h), _mm256_sub_ps(rf, ar));
      const __m256 pop = _mm256_and_ps(can, _mm256_cmp_ps(lhs, rhs, _CMP_LE_OQ));
      if (_mm256_testz_ps(pop, pop)) break;
      const __m256i c_slot = _mm256_min_epi32(
          _mm256_max_epi32(_mm256_cvtps_epi32(_mm256_sub_ps(cr, r_first)), izero), last_slot);
      const __m256i i3 = _mm256_add_epi32(_mm256_slli_epi32(c_slot, 3), lane);
      top = _mm256_add_epi32(top, _mm256_castps_si256(pop));  // -1 where popping
      ah = _mm256_blendv_ps(ah, bh, pop);
      ar = _mm256_blendv_ps(ar, br, pop);
      bh = _mm256_blendv_ps(bh, ch, pop);
      br = _mm256_blendv_ps(br, cr, pop);
      ch = _mm256_mask_i32gather_ps(ch, link_h, i3, pop, 4);
      cr = _mm256_mask_i32gather_ps(cr, link_r, i3, pop, 4);
    }
    const __m256 has = _mm256_castsi256_ps(_mm256_cmpgt_epi32(top, izero));
    const __m256 slope =
        _mm256_mul_ps(_mm256_div_ps(_mm256_sub_ps(ah, h), _mm256_sub_ps(rf, ar)), inv_metres);
    _mm256_storeu_ps(block + static_cast<std::ptrdiff_t>(k) * L,
                     _mm256_blendv_ps(nan, _mm256_blendv_ps(minus_inf, slope, has), active));

    // Push on the active lanes: slot k - lo keeps the old top (an inactive lane stores too, and
    // never reads the slot back).
    _mm256_storeu_ps(link_h + static_cast<std::ptrdiff_t>(k - lo) * L, ah);
    _mm256_storeu_ps(link_r + static_cast<std::ptrdiff_t>(k - lo) * L, ar);
    top = _mm256_sub_epi32(top, _mm256_castps_si256(active));  // +1 where active
    ch = _mm256_blendv_ps(ch, bh, active);
    cr = _mm256_blendv_ps(cr, br, active);
    bh = _mm256_blendv_ps(bh, ah, active);
    br = _mm256_blendv_ps(br, ar, active);
    ah = _mm256_blendv_ps(ah, h, active);
    ar = _mm256_blendv_ps(ar, rf, active);
  }
#endif
}

}  // namespace avx512 / avx2

#ifndef PENUMBRA_RADIAL_LANES_AVX512
namespace avx512 {  // radial_sweep_lanes_avx512.cpp
void sweep_radial_group(const RadialGroup& g, RadialScratch& sc, float* block);
}

void sweep_radial_group_lanes(const RadialGroup& g, RadialScratch& sc, float* block) {
  if (sweep_isa() == SweepIsa::kAvx512)
    avx512::sweep_radial_group(g, sc, block);
  else
    avx2::sweep_radial_group(g, sc, block);
}
#endif

#elif !defined(PENUMBRA_RADIAL_LANES_AVX512)

void sweep_radial_group_lanes(const RadialGroup& g, RadialScratch& sc, float* block) {
  sweep_radial_group_scalar(g, sc, block);
}

#endif

}  // namespace penumbra::terrain_shadow::detail
