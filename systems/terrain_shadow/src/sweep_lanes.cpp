// The line sweep, eight lines per AVX2 step (sweep_lanes.h). Timonen and Westerholm 2010.
#include "sweep_lanes.h"

#ifdef __AVX2__

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fast_atan.h"
#include "sweep_geometry.h"

namespace penumbra::terrain_shadow::detail {
namespace {

constexpr int kPad = 8;     // zero samples either side of a padded column
constexpr int kAccPad = 9;  // accumulator slots either side of the region's minor range

}  // namespace

LaneFields::LaneFields(const assets::HeightField& f)
    : stride_x(f.height + 2 * kPad + 1), stride_y(f.width + 2 * kPad + 1) {
  x_major.assign(static_cast<std::size_t>(f.width) * stride_x, 0.0f);
  y_major.assign(static_cast<std::size_t>(f.height) * stride_y, 0.0f);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      x_major[static_cast<std::size_t>(x) * stride_x + kPad + y] = f.at(x, y);
      y_major[static_cast<std::size_t>(y) * stride_y + kPad + x] = f.at(x, y);
    }
}

void sweep_azimuth_lanes(const assets::HeightField& f, const LaneFields& fields,
                         const HorizonParams& p, const TexelRect& r, int k, LaneScratch& sc,
                         float* plane) {
  const AzimuthFrame frame(f, azimuth_angle(k, p.azimuths));
  const int u0 = frame.x_major ? r.x0 : r.y0, u1 = frame.x_major ? r.x1 : r.y1;
  const int v0 = frame.x_major ? r.y0 : r.x0, v1 = frame.x_major ? r.y1 : r.x1;
  const int row = (v1 - v0) + 2 * kAccPad;  // accumulator row per major coordinate
  sc.acc.assign(static_cast<std::size_t>(u1 - u0) * row, 0.0f);
  sc.weight.assign(sc.acc.size(), 0.0f);
  const std::size_t cap = static_cast<std::size_t>(frame.major_size);
  sc.hull_h.resize(cap * 8), sc.hull_j.resize(cap * 8), sc.slope.resize(cap * 8);
  sc.rec_u.resize(cap), sc.rec_b.resize(cap), sc.rec_t.resize(cap), sc.rec_valid.resize(cap);

  const float* heights = frame.x_major ? fields.x_major.data() : fields.y_major.data();
  const int stride = frame.x_major ? fields.stride_x : fields.stride_y;
  const int bmax = frame.minor_size - 1;
  const double lo = std::min(v0 - frame.slope * u0, v0 - frame.slope * (u1 - 1));
  const double hi = std::max((v1 - 1) - frame.slope * u0, (v1 - 1) - frame.slope * (u1 - 1));
  const int c_lo = static_cast<int>(std::floor(lo)) - 1, c_hi = static_cast<int>(std::ceil(hi)) + 1;
  const int u_far = frame.step > 0 ? frame.major_size - 1 : 0;
  const int u_near = frame.step > 0 ? u0 : u1 - 1;
  const __m256 scale = _mm256_set1_ps(p.height_scale), mps = _mm256_set1_ps(frame.metres_per_step);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 minus_inf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());

  // Groups start at multiples of 8, so a line's lane (and its arithmetic) does not depend on
  // the region: a region update equals the full update bit for bit.
  const int g_lo = c_lo >= 0 ? c_lo / 8 * 8 : -((-c_lo + 7) / 8 * 8);
  for (int cg = g_lo; cg <= c_hi; cg += 8) {
    // Columns where any of the eight lines is inside the field (as the scalar sweep, widened).
    int ua = 0, ub = frame.major_size - 1;
    if (frame.slope != 0) {
      const double e[4] = {-cg / frame.slope, (bmax - cg) / frame.slope, -(cg + 7) / frame.slope,
                           (bmax - cg - 7) / frame.slope};
      ua = std::max(ua, static_cast<int>(std::floor(*std::min_element(e, e + 4))) - 1);
      ub = std::min(ub, static_cast<int>(std::ceil(*std::max_element(e, e + 4))) + 1);
    } else if (cg + 7 < 0 || cg > bmax) {
      continue;
    }
    if (frame.step > 0)
      ub = std::min(ub, u_far), ua = std::max(ua, u_near);
    else
      ua = std::max(ua, u_far), ub = std::min(ub, u_near);
    if (ua > ub) continue;

    __m256i top = _mm256_setzero_si256();  // hull size per lane
    std::size_t records = 0;
    const int u_start = frame.step > 0 ? ub : ua, u_end = frame.step > 0 ? ua : ub;
    for (int u = u_start;; u -= frame.step) {
      const double base = cg + frame.slope * u;  // lane l sits at base + l
      const int b0 = static_cast<int>(std::floor(base));
      if (b0 + 7 >= 0 && b0 <= bmax) {
        const float t = static_cast<float>(base - b0);
        const __m256i b = _mm256_add_epi32(_mm256_set1_epi32(b0), lane);
        // Inside the field: 0 <= b + t <= bmax (as AzimuthFrame::height_at).
        __m256i ok = _mm256_andnot_si256(_mm256_cmpgt_epi32(_mm256_setzero_si256(), b),
                                         _mm256_cmpgt_epi32(_mm256_set1_epi32(bmax), b));
        if (t == 0.0f) ok = _mm256_or_si256(ok, _mm256_cmpeq_epi32(b, _mm256_set1_epi32(bmax)));
        const __m256 valid = _mm256_castsi256_ps(ok);
        const float* col = heights + static_cast<std::ptrdiff_t>(u) * stride + kPad + b0;
        const __m256 h0 = _mm256_loadu_ps(col), h1 = _mm256_loadu_ps(col + 1);
        const __m256 h =
            _mm256_mul_ps(scale, _mm256_fmadd_ps(_mm256_set1_ps(t), _mm256_sub_ps(h1, h0), h0));
        const __m256 j = _mm256_set1_ps(static_cast<float>(frame.step * u));
        // Pop while the second point is at least as steep as the top (no division).
        for (;;) {
          const __m256i two = _mm256_cmpgt_epi32(top, _mm256_set1_epi32(1));
          const __m256 can = _mm256_and_ps(valid, _mm256_castsi256_ps(two));
          if (_mm256_testz_ps(can, can)) break;
          const __m256i i1 = _mm256_add_epi32(
              _mm256_slli_epi32(_mm256_max_epi32(_mm256_sub_epi32(top, _mm256_set1_epi32(1)),
                                                 _mm256_setzero_si256()),
                                3),
              lane);
          const __m256i i2 = _mm256_add_epi32(
              _mm256_slli_epi32(_mm256_max_epi32(_mm256_sub_epi32(top, _mm256_set1_epi32(2)),
                                                 _mm256_setzero_si256()),
                                3),
              lane);
          const __m256 ah = _mm256_i32gather_ps(sc.hull_h.data(), i1, 4);
          const __m256 aj = _mm256_i32gather_ps(sc.hull_j.data(), i1, 4);
          const __m256 bh = _mm256_i32gather_ps(sc.hull_h.data(), i2, 4);
          const __m256 bj = _mm256_i32gather_ps(sc.hull_j.data(), i2, 4);
          const __m256 lhs = _mm256_mul_ps(_mm256_sub_ps(bh, h), _mm256_sub_ps(aj, j));
          const __m256 rhs = _mm256_mul_ps(_mm256_sub_ps(ah, h), _mm256_sub_ps(bj, j));
          const __m256 pop = _mm256_and_ps(can, _mm256_cmp_ps(lhs, rhs, _CMP_GE_OQ));
          if (_mm256_testz_ps(pop, pop)) break;
          top = _mm256_add_epi32(top, _mm256_castps_si256(pop));  // -1 where popping
        }
        const bool record = u >= u0 && u < u1;
        if (record) {
          const __m256i has = _mm256_and_si256(ok, _mm256_cmpgt_epi32(top, _mm256_setzero_si256()));
          const __m256i i1 = _mm256_add_epi32(
              _mm256_slli_epi32(_mm256_max_epi32(_mm256_sub_epi32(top, _mm256_set1_epi32(1)),
                                                 _mm256_setzero_si256()),
                                3),
              lane);
          const __m256 ah = _mm256_i32gather_ps(sc.hull_h.data(), i1, 4);
          const __m256 aj = _mm256_i32gather_ps(sc.hull_j.data(), i1, 4);
          const __m256 s =
              _mm256_div_ps(_mm256_sub_ps(ah, h), _mm256_mul_ps(_mm256_sub_ps(aj, j), mps));
          // Nothing ahead: -inf (atan -pi/2); outside the field: 0 (weight 0, kept finite).
          const __m256 v = _mm256_blendv_ps(minus_inf, s, _mm256_castsi256_ps(has));
          _mm256_storeu_ps(sc.slope.data() + records * 8, _mm256_and_ps(v, valid));
          sc.rec_u[records] = u;
          sc.rec_b[records] = b0;
          sc.rec_t[records] = t;
          sc.rec_valid[records] = static_cast<unsigned char>(_mm256_movemask_ps(valid));
          ++records;
        }
        // Push on the lanes inside the field.
        alignas(32) float hv[8];
        alignas(32) int tv[8];
        _mm256_store_ps(hv, h);
        _mm256_store_si256(reinterpret_cast<__m256i*>(tv), top);
        const int mask = _mm256_movemask_ps(valid);
        const float jf = static_cast<float>(frame.step * u);
        for (int l = 0; l < 8; ++l)
          if (mask >> l & 1) {
            sc.hull_h[static_cast<std::size_t>(tv[l]) * 8 + l] = hv[l];
            sc.hull_j[static_cast<std::size_t>(tv[l]) * 8 + l] = jf;
          }
        top = _mm256_sub_epi32(top, _mm256_castps_si256(valid));  // +1 where valid
      }
      if (u == u_end) break;
    }

    fast_atan_array(sc.slope.data(), records * 8);
    for (std::size_t i = 0; i < records; ++i) {
      // Lane l's line lies t above texel b0 + l and 1 - t below texel b0 + l + 1.
      const int b0 = sc.rec_b[i];
      if (b0 + 8 < v0 || b0 >= v1) continue;
      __m256 angle = _mm256_loadu_ps(sc.slope.data() + i * 8);
      if (p.clamp_at_zero) angle = _mm256_max_ps(angle, _mm256_setzero_ps());
      const int m = sc.rec_valid[i];
      const __m256 valid = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
          _mm256_and_si256(_mm256_set1_epi32(m), _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128)),
          _mm256_setzero_si256()));
      const float t = sc.rec_t[i];
      const __m256 w_lo = _mm256_and_ps(valid, _mm256_set1_ps(1.0f - t));
      const __m256 w_hi = t > 0 ? _mm256_and_ps(valid, _mm256_set1_ps(t)) : _mm256_setzero_ps();
      const std::size_t at = static_cast<std::size_t>(sc.rec_u[i] - u0) * row + (b0 - v0 + kAccPad);
      float* acc = sc.acc.data() + at;
      float* wgt = sc.weight.data() + at;
      _mm256_storeu_ps(acc, _mm256_fmadd_ps(w_lo, angle, _mm256_loadu_ps(acc)));
      _mm256_storeu_ps(wgt, _mm256_add_ps(_mm256_loadu_ps(wgt), w_lo));
      _mm256_storeu_ps(acc + 1, _mm256_fmadd_ps(w_hi, angle, _mm256_loadu_ps(acc + 1)));
      _mm256_storeu_ps(wgt + 1, _mm256_add_ps(_mm256_loadu_ps(wgt + 1), w_hi));
    }
  }

  const int w = r.width();
  for (int u = u0; u < u1; ++u)
    for (int v = v0; v < v1; ++v) {
      const std::size_t i = static_cast<std::size_t>(u - u0) * row + (v - v0 + kAccPad);
      const int x = frame.x_major ? u : v, y = frame.x_major ? v : u;
      plane[static_cast<std::size_t>(y - r.y0) * w + (x - r.x0)] =
          sc.weight[i] > 0 ? sc.acc[i] / sc.weight[i] : 0.0f;
    }
}

}  // namespace penumbra::terrain_shadow::detail

#endif  // __AVX2__
