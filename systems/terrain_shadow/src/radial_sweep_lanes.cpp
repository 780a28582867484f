// One group of RadialHorizonSweep's lines, scalar and on AVX2 lanes (radial_sweep_lanes.h): the
// upper-hull sweep of [Timonen10] along lines radiating from the light's foot ([Meier13] eq. 4.22).
// Compiled twice, as sweep_lanes.cpp: here for the x86-64-v3 baseline (the scalar kernel, the
// AVX2 lanes, the run-time choice), and by radial_sweep_lanes_avx512.cpp for AVX-512
// (PENUMBRA_RADIAL_LANES_AVX512: the walk of two groups on sixteen lanes only, in namespace
// avx512; one group walks as a pair with an empty second).
#include "radial_sweep_lanes.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
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
#ifndef PENUMBRA_RADIAL_LANES_AVX512
namespace avx2 {

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
  // (Each size on its own: the scalar kernel and the AVX-512 pair walk size them otherwise.)
  if (sc.hull_r.size() < slots) sc.hull_r.resize(slots);
  if (sc.hull_h.size() < slots) sc.hull_h.resize(slots);
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
    const __m256 s0 = _mm256_i32gather_ps(g.heights, i0, 4);
    const __m256 s1 = _mm256_i32gather_ps(g.heights, i1, 4);
    const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(k - lo) * L;
    _mm256_storeu_ps(
        sc.h.data() + at,
        _mm256_mul_ps(scale, _mm256_add_ps(s0, _mm256_mul_ps(fv, _mm256_sub_ps(s1, s0)))));
    _mm256_storeu_ps(sc.active.data() + at, active);
  }

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
}

}  // namespace avx2
#else
namespace avx512 {
namespace {

// Lanes 0-7 and 8-15 of a 512-bit vector from two 256-bit halves, and back. Here and below the
// masked forms with every lane (the same instructions): GCC 12 warns that the plain forms'
// undefined pass-through is uninitialized.
[[gnu::always_inline]] inline __m512 join(__m256 lo, __m256 hi) {
  return _mm512_mask_broadcast_f32x8(_mm512_maskz_broadcast_f32x8(0x00ff, lo), 0xff00, hi);
}
[[gnu::always_inline]] inline __m512i join(__m256i lo, __m256i hi) {
  return _mm512_mask_broadcast_i32x8(_mm512_maskz_broadcast_i32x8(0x00ff, lo), 0xff00, hi);
}
[[gnu::always_inline]] inline __m256 half(__m512 v, int upper) {
  return upper ? _mm512_maskz_extractf32x8_ps(0xff, v, 1)
               : _mm512_maskz_extractf32x8_ps(0xff, v, 0);
}
[[gnu::always_inline]] inline __m256i half(__m512i v, int upper) {
  return upper ? _mm512_maskz_extracti32x8_epi32(0xff, v, 1)
               : _mm512_maskz_extracti32x8_epi32(0xff, v, 0);
}
// The low 32 bits of each 64-bit element of two vectors of eight, as sixteen floats.
[[gnu::always_inline]] inline __m512 low_words(__m512i lo, __m512i hi) {
  return _mm512_castsi512_ps(
      join(_mm512_maskz_cvtepi64_epi32(0xff, lo), _mm512_maskz_cvtepi64_epi32(0xff, hi)));
}

}  // namespace

// sweep_radial_group's walk on sixteen AVX-512 lanes: lanes 0-7 are group a's, 8-15 group b's,
// per lane the same operations (so the same floats). As the line sweep's walk16: the lanes'
// masks in mask registers, a fourth hull point (d) in registers with per lane how many of a,
// b, c, d are current (c is refilled from the links only when a pop leaves it stale), and
// each link's (h, r) side by side, one 64-bit gather element: (h, r) at slot * 16 + l.
void sweep_radial_pair(const RadialGroup& a, const RadialGroup& b, RadialScratch& sc,
                       float* block_a, float* block_b) {
  int lo_a, hi_a, lo_b, hi_b;
  swept_columns(a, lo_a, hi_a);
  swept_columns(b, lo_b, hi_b);
  // The union of both groups' swept columns (a group sweeping none has lo = hi = 0).
  const bool has_a = lo_a < hi_a, has_b = lo_b < hi_b;
  const int lo = has_a && has_b ? std::min(lo_a, lo_b) : (has_a ? lo_a : lo_b);
  const int hi = std::max(hi_a, hi_b);
  const RadialGroup* groups[2] = {&a, &b};
  float* blocks[2] = {block_a, block_b};
  for (int g = 0; g < 2; ++g) {  // columns of each block the walk below does not write
    const int width = groups[g]->width;
    fill_nan(blocks[g], 0, std::min(lo, width));
    fill_nan(blocks[g], std::max(hi, std::min(lo, width)), width);
  }
  if (lo >= hi) return;
  constexpr int W = 2 * L;
  const std::size_t slots = static_cast<std::size_t>(hi - lo + 1) * W;
  if (sc.hull_h.size() < 2 * slots) sc.hull_h.resize(2 * slots);
  const std::size_t columns = static_cast<std::size_t>(hi - lo) * W;
  if (sc.h.size() < columns) sc.h.resize(columns), sc.active.resize(columns);
  float* links = sc.hull_h.data();
  auto* active_masks = reinterpret_cast<unsigned char*>(sc.active.data());

  const __m512d v0 = _mm512_set1_pd(a.v0), m_a = _mm512_loadu_pd(a.m.data()),
                m_b = _mm512_loadu_pd(b.m.data());
  const __m512i first = join(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(a.first.data())),
                             _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b.first.data())));
  const __m512i end = join(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(a.end.data())),
                           _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b.end.data())));
  const __m512 inv_metres =
      join(_mm256_loadu_ps(a.inv_metres.data()), _mm256_loadu_ps(b.inv_metres.data()));
  const __m512 scale = _mm512_set1_ps(a.height_scale), almost_one = _mm512_set1_ps(1 - 1e-5f);
  const __m512 nan = _mm512_set1_ps(kNaN), minus_inf = _mm512_set1_ps(kMinusInf);
  const __m512 zero = _mm512_setzero_ps();
  const __m512i izero = _mm512_setzero_si512(), one = _mm512_set1_epi32(1);
  const __m512i v_last = _mm512_set1_epi32(a.size_v - 1), stride_v = _mm512_set1_epi32(a.stride_v);
  const __m512 r_first = _mm512_set1_ps(static_cast<float>(a.r_near + lo));
  const __m512i last_slot = _mm512_set1_epi32(hi - lo);

  // The samples, all columns first (as sweep_radial_group).
  for (int k = lo; k < hi; ++k) {
    const __m512d rd = _mm512_set1_pd(a.r_near + k);
    const __m512d va = _mm512_add_pd(v0, _mm512_mul_pd(rd, m_a));
    const __m512d vb = _mm512_add_pd(v0, _mm512_mul_pd(rd, m_b));
    const __m512d fa =
        _mm512_maskz_roundscale_pd(0xff, va, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m512d fb =
        _mm512_maskz_roundscale_pd(0xff, vb, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    __m512i vi = join(_mm512_maskz_cvttpd_epi32(0xff, fa), _mm512_maskz_cvttpd_epi32(0xff, fb));
    __m512 fv = join(_mm512_maskz_cvtpd_ps(0xff, _mm512_sub_pd(va, fa)),
                     _mm512_maskz_cvtpd_ps(0xff, _mm512_sub_pd(vb, fb)));
    const __mmask16 bump = _mm512_cmp_ps_mask(fv, almost_one, _CMP_GT_OQ);
    vi = _mm512_mask_add_epi32(vi, bump, vi, one);
    fv = _mm512_maskz_mov_ps(static_cast<__mmask16>(~bump), fv);
    const __mmask16 border = _mm512_cmpgt_epi32_mask(izero, vi) |
                             _mm512_cmpgt_epi32_mask(vi, _mm512_sub_epi32(v_last, one));
    vi = _mm512_maskz_min_epi32(0xffff, _mm512_maskz_max_epi32(0xffff, vi, izero), v_last);
    fv = _mm512_maskz_mov_ps(static_cast<__mmask16>(~border), fv);
    const __m512i kv = _mm512_set1_epi32(k);
    const __mmask16 active = _mm512_cmple_epi32_mask(first, kv) & _mm512_cmpgt_epi32_mask(end, kv);
    const __m512i i0 = _mm512_add_epi32(_mm512_set1_epi32((a.u_first + a.sign * k) * a.stride_u),
                                        _mm512_mullo_epi32(vi, stride_v));
    const __mmask16 up = _mm512_cmp_ps_mask(fv, zero, _CMP_GT_OQ);
    __m512 s0, s1;
    if (a.stride_v == 1 && a.size_v >= 2) {
      // A lane's two samples as one 64-bit element (sweep_radial_group), eight lanes a gather.
      const __mmask16 last = _mm512_cmpeq_epi32_mask(vi, v_last);
      const __m512i at = _mm512_mask_sub_epi32(i0, last, i0, one);
      const __m512i p_lo =
          _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), 0xff, half(at, 0), a.heights, 4);
      const __m512i p_hi =
          _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), 0xff, half(at, 1), a.heights, 4);
      const __m512 left = low_words(p_lo, p_hi);
      const __m512 right = low_words(_mm512_maskz_srli_epi64(0xff, p_lo, 32),
                                     _mm512_maskz_srli_epi64(0xff, p_hi, 32));
      s0 = _mm512_mask_blend_ps(last, left, right);
      s1 = _mm512_mask_blend_ps(up, s0, right);
    } else {
      s0 = _mm512_mask_i32gather_ps(zero, 0xffff, i0, a.heights, 4);
      s1 = _mm512_mask_i32gather_ps(zero, 0xffff, _mm512_mask_add_epi32(i0, up, i0, stride_v),
                                    a.heights, 4);
    }
    const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(k - lo) * W;
    _mm512_storeu_ps(
        sc.h.data() + at,
        _mm512_mul_ps(scale, _mm512_add_ps(s0, _mm512_mul_ps(fv, _mm512_sub_ps(s1, s0)))));
    std::memcpy(active_masks + 2 * (k - lo), &active, 2);
  }

  // The walk (sweep_radial_group's, sixteen lanes).
  const __m512i two = _mm512_set1_epi32(2), three = _mm512_set1_epi32(3),
                four = _mm512_set1_epi32(4);
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i pairs_lo =
      _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
  const __m512i pairs_hi =
      _mm512_setr_epi32(8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31);
  __m512i top = izero, depth = izero;
  __m512 ah = zero, ar = zero, bh = zero, br = zero, ch = zero, cr = zero, dh = zero, dr = zero;
  for (int k = lo; k < hi; ++k) {
    const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(k - lo) * W;
    const __m512 rf = _mm512_set1_ps(static_cast<float>(a.r_near + k));
    const __m512 h = _mm512_loadu_ps(sc.h.data() + at);
    __mmask16 active;
    std::memcpy(&active, active_masks + 2 * (k - lo), 2);
    for (;;) {
      const __mmask16 can = _mm512_mask_cmpgt_epi32_mask(active, top, one);
      const __m512 lhs = _mm512_mul_ps(_mm512_sub_ps(ah, h), _mm512_sub_ps(rf, br));
      const __m512 rhs = _mm512_mul_ps(_mm512_sub_ps(bh, h), _mm512_sub_ps(rf, ar));
      const __mmask16 pop = _mm512_mask_cmp_ps_mask(can, lhs, rhs, _CMP_LE_OQ);
      if (pop == 0) break;
      top = _mm512_mask_sub_epi32(top, pop, top, one);
      depth = _mm512_mask_sub_epi32(depth, pop, depth, one);
      ah = _mm512_mask_mov_ps(ah, pop, bh), ar = _mm512_mask_mov_ps(ar, pop, br);
      bh = _mm512_mask_mov_ps(bh, pop, ch), br = _mm512_mask_mov_ps(br, pop, cr);
      ch = _mm512_mask_mov_ps(ch, pop, dh), cr = _mm512_mask_mov_ps(cr, pop, dr);
      const __mmask16 refill =
          _mm512_mask_cmpgt_epi32_mask(_mm512_mask_cmpgt_epi32_mask(pop, three, depth), top, two);
      if (refill == 0) continue;
      const __m512i b_slot = _mm512_maskz_min_epi32(
          0xffff,
          _mm512_maskz_max_epi32(
              0xffff, _mm512_maskz_cvtps_epi32(0xffff, _mm512_sub_ps(br, r_first)), izero),
          last_slot);
      const __m512i i4 = _mm512_add_epi32(_mm512_maskz_slli_epi32(0xffff, b_slot, 4), lane);
      const __m512i p_lo = _mm512_mask_i32gather_epi64(
          _mm512_setzero_si512(), static_cast<__mmask8>(refill), half(i4, 0), links, 8);
      const __m512i p_hi = _mm512_mask_i32gather_epi64(
          _mm512_setzero_si512(), static_cast<__mmask8>(refill >> 8), half(i4, 1), links, 8);
      ch = _mm512_mask_mov_ps(ch, refill, low_words(p_lo, p_hi));
      cr = _mm512_mask_mov_ps(cr, refill,
                              low_words(_mm512_maskz_srli_epi64(0xff, p_lo, 32),
                                        _mm512_maskz_srli_epi64(0xff, p_hi, 32)));
      depth = _mm512_mask_mov_epi32(depth, refill, three);
    }
    const __mmask16 has = _mm512_cmpgt_epi32_mask(top, izero);
    const __m512 slope =
        _mm512_mul_ps(_mm512_div_ps(_mm512_sub_ps(ah, h), _mm512_sub_ps(rf, ar)), inv_metres);
    const __m512 out =
        _mm512_mask_blend_ps(active, nan, _mm512_mask_blend_ps(has, minus_inf, slope));
    if (k < a.width) _mm256_storeu_ps(block_a + static_cast<std::ptrdiff_t>(k) * L, half(out, 0));
    if (k < b.width) _mm256_storeu_ps(block_b + static_cast<std::ptrdiff_t>(k) * L, half(out, 1));
    // Push on the active lanes: slot k - lo keeps the old top (every lane stores).
    _mm512_storeu_ps(links + 2 * at, _mm512_permutex2var_ps(ah, pairs_lo, ar));
    _mm512_storeu_ps(links + 2 * at + W, _mm512_permutex2var_ps(ah, pairs_hi, ar));
    if (active == 0xffff) {
      top = _mm512_add_epi32(top, one);
      depth = _mm512_maskz_min_epi32(0xffff, _mm512_add_epi32(depth, one), four);
      dh = ch, dr = cr, ch = bh, cr = br, bh = ah, br = ar, ah = h, ar = rf;
      continue;
    }
    top = _mm512_mask_add_epi32(top, active, top, one);
    depth = _mm512_mask_min_epi32(depth, active, _mm512_add_epi32(depth, one), four);
    dh = _mm512_mask_mov_ps(dh, active, ch), dr = _mm512_mask_mov_ps(dr, active, cr);
    ch = _mm512_mask_mov_ps(ch, active, bh), cr = _mm512_mask_mov_ps(cr, active, br);
    bh = _mm512_mask_mov_ps(bh, active, ah), br = _mm512_mask_mov_ps(br, active, ar);
    ah = _mm512_mask_mov_ps(ah, active, h), ar = _mm512_mask_mov_ps(ar, active, rf);
  }
}

// One group: the pair walk with a second group of empty lanes (the same floats for the first;
// the walk of sixteen lanes costs about what one of eight did).
void sweep_radial_group(const RadialGroup& g, RadialScratch& sc, float* block) {
  RadialGroup none = g;
  none.width = 0;
  none.first.fill(0);
  none.end.fill(0);
  sweep_radial_pair(g, none, sc, block, nullptr);
}

}  // namespace avx512
#endif

#ifndef PENUMBRA_RADIAL_LANES_AVX512
namespace avx512 {  // radial_sweep_lanes_avx512.cpp
void sweep_radial_group(const RadialGroup& g, RadialScratch& sc, float* block);
void sweep_radial_pair(const RadialGroup& a, const RadialGroup& b, RadialScratch& sc,
                       float* block_a, float* block_b);
}  // namespace avx512

void sweep_radial_pair_lanes(const RadialGroup& a, const RadialGroup& b, RadialScratch& sc,
                             float* block_a, float* block_b) {
  if (sweep_isa() == SweepIsa::kAvx512)
    return avx512::sweep_radial_pair(a, b, sc, block_a, block_b);
  avx2::sweep_radial_group(a, sc, block_a);
  avx2::sweep_radial_group(b, sc, block_b);
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

void sweep_radial_pair_lanes(const RadialGroup& a, const RadialGroup& b, RadialScratch& sc,
                             float* block_a, float* block_b) {
  sweep_radial_group_scalar(a, sc, block_a);
  sweep_radial_group_scalar(b, sc, block_b);
}

#endif

}  // namespace penumbra::terrain_shadow::detail
