// The line sweep, eight lines per AVX2 step (sweep_lanes.h). Timonen and Westerholm 2010.
#include "sweep_lanes.h"

#ifdef __AVX2__

#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "fast_math.h"
#include "sweep_geometry.h"

namespace penumbra::terrain_shadow::detail {
namespace {

constexpr int kPad = 8;     // zero samples either side of a padded column
constexpr int kAccPad = 9;  // accumulator slots either side of the region's minor range

}  // namespace

LaneFields::LaneFields(const data::HeightField& f)
    : stride_x(f.height + 2 * kPad + 1), stride_y(f.width + 2 * kPad + 1) {
  x_major.assign(static_cast<std::size_t>(f.width) * stride_x, 0.0f);
  y_major.assign(static_cast<std::size_t>(f.height) * stride_y, 0.0f);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      x_major[static_cast<std::size_t>(x) * stride_x + kPad + y] = f.at(x, y);
      y_major[static_cast<std::size_t>(y) * stride_y + kPad + x] = f.at(x, y);
    }
}

namespace {

// What every group of an azimuth shares.
struct Sweep {
  AzimuthFrame frame;
  const float* heights;  // padded copy whose minor axis is contiguous
  int stride, bmax;
  bool clamp;
  float scale;

  Sweep(const data::HeightField& f, const LaneFields& fields, const HorizonParams& p, double phi)
      : frame(f, phi),
        heights(frame.x_major ? fields.x_major.data() : fields.y_major.data()),
        stride(frame.x_major ? fields.stride_x : fields.stride_y),
        bmax(frame.minor_size - 1),
        clamp(p.clamp_at_zero),
        scale(p.height_scale) {}

  // First line of the group holding line c: groups start at multiples of 8, so a line's lane
  // (and its arithmetic) never depends on which lines or region were asked for.
  static int group_of(int c) { return c >= 0 ? c / 8 * 8 : -((-c + 7) / 8 * 8); }
  int far_end() const { return frame.step > 0 ? frame.major_size - 1 : 0; }

  // Sweeps lines cg..cg+7 from the far end of the field down to u_stop, recording the
  // receivers with major coordinate in [rec_lo, rec_hi) as angles; returns how many.
  std::size_t run_group(int cg, int u_stop, int rec_lo, int rec_hi, LaneScratch& sc) const;
};

std::size_t Sweep::run_group(int cg, int u_stop, int rec_lo, int rec_hi, LaneScratch& sc) const {
  // Columns where any of the eight lines is inside the field (widened by one).
  int ua = 0, ub = frame.major_size - 1;
  if (frame.slope != 0) {
    const double e[4] = {-cg / frame.slope, (bmax - cg) / frame.slope, -(cg + 7) / frame.slope,
                         (bmax - cg - 7) / frame.slope};
    ua = std::max(ua, static_cast<int>(std::floor(*std::min_element(e, e + 4))) - 1);
    ub = std::min(ub, static_cast<int>(std::ceil(*std::max_element(e, e + 4))) + 1);
  } else if (cg + 7 < 0 || cg > bmax) {
    return 0;
  }
  if (frame.step > 0)
    ub = std::min(ub, far_end()), ua = std::max(ua, u_stop);
  else
    ua = std::max(ua, far_end()), ub = std::min(ub, u_stop);
  if (ua > ub) return 0;

  const std::size_t cap = static_cast<std::size_t>(frame.major_size);
  sc.hull_h.resize(cap * 8), sc.hull_j.resize(cap * 8), sc.slope.resize(cap * 8);
  sc.rec_u.resize(cap), sc.rec_b.resize(cap), sc.rec_t.resize(cap), sc.rec_valid.resize(cap);
  const __m256 vscale = _mm256_set1_ps(scale), mps = _mm256_set1_ps(frame.metres_per_step);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 minus_inf = _mm256_set1_ps(-std::numeric_limits<float>::infinity());
  auto index = [&](__m256i top, int below) {  // hull slot top - below of every lane, >= 0
    const __m256i d =
        _mm256_max_epi32(_mm256_sub_epi32(top, _mm256_set1_epi32(below)), _mm256_setzero_si256());
    return _mm256_add_epi32(_mm256_slli_epi32(d, 3), lane);
  };

  __m256i top = _mm256_setzero_si256();  // hull size per lane
  // The top two hull points of every lane live in registers (a = top - 1, b = top - 2): the
  // common step (no pop, or one) then reads no memory; the hull arrays hold the full stacks.
  __m256 ah = _mm256_setzero_ps(), aj = _mm256_setzero_ps();
  __m256 bh = _mm256_setzero_ps(), bj = _mm256_setzero_ps();
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
          _mm256_mul_ps(vscale, _mm256_fmadd_ps(_mm256_set1_ps(t), _mm256_sub_ps(h1, h0), h0));
      const float jf = static_cast<float>(frame.step * u);
      const __m256 j = _mm256_set1_ps(jf);
      // Pop while the second point is at least as steep as the top (compared without
      // dividing; Timonen 2010, sec. 4), on every lane that still needs it.
      for (;;) {
        const __m256 can = _mm256_and_ps(
            valid, _mm256_castsi256_ps(_mm256_cmpgt_epi32(top, _mm256_set1_epi32(1))));
        const __m256 lhs = _mm256_mul_ps(_mm256_sub_ps(bh, h), _mm256_sub_ps(aj, j));
        const __m256 rhs = _mm256_mul_ps(_mm256_sub_ps(ah, h), _mm256_sub_ps(bj, j));
        const __m256 pop = _mm256_and_ps(can, _mm256_cmp_ps(lhs, rhs, _CMP_GE_OQ));
        if (_mm256_testz_ps(pop, pop)) break;
        top = _mm256_add_epi32(top, _mm256_castps_si256(pop));  // -1 where popping
        ah = _mm256_blendv_ps(ah, bh, pop);
        aj = _mm256_blendv_ps(aj, bj, pop);
        const __m256i i2 = index(top, 2);  // the new second point, from memory
        bh = _mm256_blendv_ps(bh, _mm256_i32gather_ps(sc.hull_h.data(), i2, 4), pop);
        bj = _mm256_blendv_ps(bj, _mm256_i32gather_ps(sc.hull_j.data(), i2, 4), pop);
      }
      if (u >= rec_lo && u < rec_hi) {
        const __m256i has = _mm256_and_si256(ok, _mm256_cmpgt_epi32(top, _mm256_setzero_si256()));
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
      // Push on the lanes inside the field. AVX2 has no scatter: eight scalar stores, on every
      // lane (a lane outside the field writes above its stack, which its top does not reach).
      alignas(32) float hv[8];
      alignas(32) int tv[8];
      _mm256_store_ps(hv, h);
      _mm256_store_si256(reinterpret_cast<__m256i*>(tv), top);
      for (int l = 0; l < 8; ++l) {
        sc.hull_h[static_cast<std::size_t>(tv[l]) * 8 + l] = hv[l];
        sc.hull_j[static_cast<std::size_t>(tv[l]) * 8 + l] = jf;
      }
      top = _mm256_sub_epi32(top, _mm256_castps_si256(valid));  // +1 where valid
      bh = _mm256_blendv_ps(bh, ah, valid);
      bj = _mm256_blendv_ps(bj, aj, valid);
      ah = _mm256_blendv_ps(ah, h, valid);
      aj = _mm256_blendv_ps(aj, j, valid);
    }
    if (u == u_end) break;
  }
  fast_atan_array(sc.slope.data(), records * 8);
  if (clamp)
    for (std::size_t i = 0; i < records * 8; ++i) sc.slope[i] = std::max(sc.slope[i], 0.0f);
  return records;
}

// Adds a group's records into acc / weight (layout [u - u0][v - v0 + kAccPad], `row` floats per
// u): lane l's line lies t above texel b0 + l and 1 - t below texel b0 + l + 1.
void scatter(LaneScratch& sc, std::size_t records, int u0, int v0, int v1, int row) {
  float* acc_base = sc.acc.data();
  float* wgt_base = sc.weight.data();
  const __m256i bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  for (std::size_t i = 0; i < records; ++i) {
    const int b0 = sc.rec_b[i];
    if (b0 + 8 < v0 || b0 >= v1) continue;
    const __m256 angle = _mm256_loadu_ps(sc.slope.data() + i * 8);
    const __m256 valid = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
        _mm256_and_si256(_mm256_set1_epi32(sc.rec_valid[i]), bits), _mm256_setzero_si256()));
    const float t = sc.rec_t[i];
    const __m256 w_lo = _mm256_and_ps(valid, _mm256_set1_ps(1.0f - t));
    const __m256 w_hi = t > 0 ? _mm256_and_ps(valid, _mm256_set1_ps(t)) : _mm256_setzero_ps();
    const std::size_t at = static_cast<std::size_t>(sc.rec_u[i] - u0) * row + (b0 - v0 + kAccPad);
    float* acc = acc_base + at;
    float* wgt = wgt_base + at;
    _mm256_storeu_ps(acc, _mm256_fmadd_ps(w_lo, angle, _mm256_loadu_ps(acc)));
    _mm256_storeu_ps(wgt, _mm256_add_ps(_mm256_loadu_ps(wgt), w_lo));
    _mm256_storeu_ps(acc + 1, _mm256_fmadd_ps(w_hi, angle, _mm256_loadu_ps(acc + 1)));
    _mm256_storeu_ps(wgt + 1, _mm256_add_ps(_mm256_loadu_ps(wgt + 1), w_hi));
  }
}

}  // namespace

void sweep_azimuth_lanes(const data::HeightField& f, const LaneFields& fields,
                         const HorizonParams& p, const TexelRect& r, int k, LaneScratch& sc,
                         float* plane) {
  sweep_direction_lanes(f, fields, p, r, azimuth_angle(k, p.azimuths), sc, plane);
}

void sweep_direction_lanes(const data::HeightField& f, const LaneFields& fields,
                           const HorizonParams& p, const TexelRect& r, double phi, LaneScratch& sc,
                           float* plane) {
  const Sweep sw(f, fields, p, phi);
  const AzimuthFrame& frame = sw.frame;
  const int u0 = frame.x_major ? r.x0 : r.y0, u1 = frame.x_major ? r.x1 : r.y1;
  const int v0 = frame.x_major ? r.y0 : r.x0, v1 = frame.x_major ? r.y1 : r.x1;
  const int row = (v1 - v0) + 2 * kAccPad;
  sc.acc.assign(static_cast<std::size_t>(u1 - u0) * row, 0.0f);
  sc.weight.assign(sc.acc.size(), 0.0f);
  // Lines b = c + slope * u with integer c bracketing every texel of the region.
  const double lo = std::min(v0 - frame.slope * u0, v0 - frame.slope * (u1 - 1));
  const double hi = std::max((v1 - 1) - frame.slope * u0, (v1 - 1) - frame.slope * (u1 - 1));
  const int c_lo = static_cast<int>(std::floor(lo)) - 1, c_hi = static_cast<int>(std::ceil(hi)) + 1;
  const int u_near = frame.step > 0 ? u0 : u1 - 1;  // sweep down to the region's near edge
  for (int cg = Sweep::group_of(c_lo); cg <= c_hi; cg += 8)
    scatter(sc, sw.run_group(cg, u_near, u0, u1, sc), u0, v0, v1, row);

  const int w = r.width();
  for (int u = u0; u < u1; ++u)
    for (int v = v0; v < v1; ++v) {
      const std::size_t i = static_cast<std::size_t>(u - u0) * row + (v - v0 + kAccPad);
      const int x = frame.x_major ? u : v, y = frame.x_major ? v : u;
      plane[static_cast<std::size_t>(y - r.y0) * w + (x - r.x0)] =
          sc.weight[i] > 0 ? sc.acc[i] / sc.weight[i] : 0.0f;
    }
}

std::size_t sweep_azimuth_lines_through(const data::HeightField& f, const LaneFields& fields,
                                        const HorizonParams& p, const TexelRect& edited, int k,
                                        LaneScratch& sc, HorizonGrid& out, unsigned char* changed) {
  const Sweep sw(f, fields, p, azimuth_angle(k, p.azimuths));
  const AzimuthFrame& frame = sw.frame;
  // The edit box in (major, minor), widened by one sample (lines interpolate between rows).
  const int ua = std::max((frame.x_major ? edited.x0 : edited.y0) - 1, 0);
  const int ub = std::min((frame.x_major ? edited.x1 : edited.y1), frame.major_size - 1);
  const int va = (frame.x_major ? edited.y0 : edited.x0) - 1;
  const int vb = (frame.x_major ? edited.y1 : edited.x1);
  // Lines passing within a row of the box, plus one either side: every texel one of these
  // lines touches then has both its lines recomputed.
  const int c_first =
      static_cast<int>(std::floor(std::min(va - frame.slope * ua, va - frame.slope * ub))) - 2;
  const int c_last =
      static_cast<int>(std::ceil(std::max(vb - frame.slope * ua, vb - frame.slope * ub))) + 2;
  const int major = frame.major_size, minor = frame.minor_size;
  const int row = minor + 2 * kAccPad;
  if (sc.acc.size() < static_cast<std::size_t>(major) * row) {
    sc.acc.resize(static_cast<std::size_t>(major) * row);
    sc.weight.resize(sc.acc.size());
  }
  // Texels whose two lines are both in [c_first, c_last]: c_first <= v - slope u < c_last.
  auto texel_range = [&](int u, int& lo, int& hi) {
    lo = std::max(static_cast<int>(std::ceil(c_first + frame.slope * u)), 0);
    hi = std::min(static_cast<int>(std::ceil(c_last + frame.slope * u)), minor);  // exclusive
  };
  for (int u = 0; u < major; ++u) {
    int lo, hi;
    texel_range(u, lo, hi);
    for (int v = lo; v < hi; ++v) {
      sc.acc[static_cast<std::size_t>(u) * row + v + kAccPad] = 0;
      sc.weight[static_cast<std::size_t>(u) * row + v + kAccPad] = 0;
    }
  }
  const int u_near = frame.step > 0 ? 0 : major - 1;
  for (int cg = Sweep::group_of(c_first); cg <= c_last; cg += 8)
    scatter(sc, sw.run_group(cg, u_near, 0, major, sc), 0, 0, minor, row);

  std::size_t pairs = 0;
  for (int u = 0; u < major; ++u) {
    int lo, hi;
    texel_range(u, lo, hi);
    for (int v = lo; v < hi; ++v, ++pairs) {
      const std::size_t i = static_cast<std::size_t>(u) * row + v + kAccPad;
      const float a = sc.weight[i] > 0 ? sc.acc[i] / sc.weight[i] : 0.0f;
      const int x = frame.x_major ? u : v, y = frame.x_major ? v : u;
      float& dst = out.texel(x, y)[k];
      if (dst != a) {
        dst = a;
        std::atomic_ref<unsigned char>(changed[static_cast<std::size_t>(y) * f.width + x])
            .store(1, std::memory_order_relaxed);
      }
    }
  }
  return pairs;
}

}  // namespace penumbra::terrain_shadow::detail

#endif  // __AVX2__
