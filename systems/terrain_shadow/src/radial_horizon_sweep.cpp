#include "penumbra/systems/terrain_shadow/radial_horizon_sweep.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "fast_math.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "radial_lookup.h"
#include "radial_sweep_lanes.h"
#include "sweep_lanes.h"

namespace penumbra::terrain_shadow {
namespace {

using detail::kHalfPi;

}  // namespace

namespace {

// floor / ceil of v as an int, v first clamped to [lo - 1, hi + 1] (far-away feet).
int clamped_floor(double v, int lo, int hi) {
  return static_cast<int>(std::floor(std::clamp(v, lo - 1.0, hi + 1.0)));
}
int clamped_ceil(double v, int lo, int hi) {
  return static_cast<int>(std::ceil(std::clamp(v, lo - 1.0, hi + 1.0)));
}

}  // namespace

void RadialHorizonSweep::limit_lines(Side& side, std::span<const TexelRect> regions) const {
  // horizon() reads lines l0 and l0 + 1 at column k, l0 = floor(m J - j_lo) for the texel's
  // slope m = rv / ru about the side's major axis. Over a rectangle with ru > 0, m is extreme at
  // its corners; one line of margin either side covers the rounding of horizon()'s floats.
  side.line_end.assign(static_cast<std::size_t>(side.lines), 0);
  const float fu = side.x_major ? foot_.x : foot_.y, fv = side.x_major ? foot_.y : foot_.x;
  for (const TexelRect& r : regions) {
    if (r.empty()) continue;
    const int ua = side.x_major ? r.x0 : r.y0, ub = (side.x_major ? r.x1 : r.y1) - 1;
    const int va = side.x_major ? r.y0 : r.x0, vb = (side.x_major ? r.y1 : r.x1) - 1;
    const int ka = side.sign * (ua - side.u_first), kb = side.sign * (ub - side.u_first);
    const int k_lo = std::max(std::min(ka, kb), 0);
    const int k_hi = std::min(std::max(ka, kb), side.columns - 1);
    if (k_lo > k_hi) continue;
    const float ru_lo =
        std::max(side.sign * (static_cast<float>(side.u_first + side.sign * k_lo) - fu), 1e-6f);
    const float ru_hi = side.sign * (static_cast<float>(side.u_first + side.sign * k_hi) - fu);
    float m_lo = 1, m_hi = -1;
    for (const float rv : {static_cast<float>(va) - fv, static_cast<float>(vb) - fv})
      for (const float ru : {ru_lo, std::max(ru_hi, ru_lo)}) {
        const float m = std::clamp(rv / ru, -1.0f, 1.0f);
        m_lo = std::min(m_lo, m);
        m_hi = std::max(m_hi, m);
      }
    const float j0 = static_cast<float>(side.j_lo);
    const int last = side.lines - 1;
    const int l_lo = std::clamp(static_cast<int>(std::floor(m_lo * side.lines_per_slope - j0)) - 1,
                                0, std::max(last - 1, 0));
    const int l_hi = std::clamp(static_cast<int>(std::floor(m_hi * side.lines_per_slope - j0)) + 2,
                                std::min(1, last), last);
    for (int l = l_lo; l <= l_hi; ++l)
      side.line_end[static_cast<std::size_t>(l)] =
          std::max(side.line_end[static_cast<std::size_t>(l)], k_hi + 1);
  }
}

void RadialHorizonSweep::run(const data::HeightField& f, float height_scale, glm::vec2 foot,
                             float reach, std::span<const TexelRect> regions) {
  field_ = &f;
  height_scale_ = height_scale;
  foot_ = foot / f.cell_size;
  foot_inside_ = foot_.x >= 0 && foot_.y >= 0 && foot_.x <= static_cast<float>(f.width - 1) &&
                 foot_.y <= static_cast<float>(f.height - 1);
  // Each side's groups of lines, then one parallel loop over all four sides' pairs of groups (a
  // loop per side waited for its slowest group four times).
  std::array<detail::RadialGroup, 4> bases;
  std::array<int, 5> pair_start{};
  for (int index = 0; index < 4; ++index) {
    Side& side = sides_[index];
    pair_start[index + 1] = pair_start[index];
    side.x_major = index < 2;
    side.sign = index % 2 == 0 ? 1 : -1;
    const int size_u = side.x_major ? f.width : f.height;
    const int size_v = side.x_major ? f.height : f.width;
    const double u0 = side.x_major ? foot.x / f.cell_size : foot.y / f.cell_size;
    const double v0 = side.x_major ? foot.y / f.cell_size : foot.x / f.cell_size;
    // Columns at r = sign (u - u0) >= 0 inside the field.
    int u_last;
    if (side.sign > 0) {
      side.u_first = std::max(0, clamped_ceil(u0, 0, size_u - 1));
      u_last = size_u - 1;
      side.columns = u_last - side.u_first + 1;
    } else {
      side.u_first = std::min(size_u - 1, clamped_floor(u0, 0, size_u - 1));
      u_last = 0;
      side.columns = side.u_first - u_last + 1;
    }
    side.lines = 0;
    if (side.columns <= 0) continue;
    const double r_near = side.sign * (side.u_first - u0), r_far = side.sign * (u_last - u0);
    const double lines_per_slope = std::max(1.0, std::ceil(r_far));
    side.lines_per_slope = static_cast<float>(lines_per_slope);
    // Columns beyond the reach are not swept (the lines stay those of the whole field, so the
    // horizons within the reach are the same as without it).
    const double reach_columns = std::ceil(static_cast<double>(reach) / f.cell_size) + 1 - r_near;
    if (reach_columns < side.columns) side.columns = std::max(1, static_cast<int>(reach_columns));
    // Only the lines that reach the field: v = v0 + r m in [0, size_v - 1] for some r.
    double m_lo = -1, m_hi = 1;
    if (r_near > 0) {
      m_lo = std::max(m_lo, std::min(-v0 / r_near, -v0 / r_far));
      m_hi = std::min(m_hi, std::max((size_v - 1 - v0) / r_near, (size_v - 1 - v0) / r_far));
    }
    const double j_lo = std::floor(m_lo * lines_per_slope),
                 j_hi = std::ceil(m_hi * lines_per_slope);
    if (j_lo > j_hi) continue;
    side.j_lo = static_cast<int>(j_lo);
    side.lines = static_cast<int>(j_hi - j_lo) + 1;
    const int groups = (side.lines + detail::kRadialLanes - 1) / detail::kRadialLanes;
    pair_start[index + 1] += (groups + 1) / 2;
    side.angle.resize(static_cast<std::size_t>(groups) * detail::kRadialLanes * side.columns);
    side.line_end.clear();
    if (!regions.empty()) limit_lines(side, regions);
    detail::RadialGroup& base = bases[index];
    base.heights = f.heights.data();
    base.stride_u = side.x_major ? 1 : f.width;
    base.stride_v = side.x_major ? f.width : 1;
    base.size_v = size_v;
    base.u_first = side.u_first;
    base.sign = side.sign;
    base.v0 = v0;
    base.r_near = r_near;
    base.height_scale = height_scale;
  }
  // Group `group` of side `index`: its lines' slopes and columns (width 0: it serves no region,
  // or lies past the side's last line).
  auto group_of = [&](int index, int group) {
    const Side& side = sides_[index];
    const detail::RadialGroup& base = bases[index];
    const double v_max = base.size_v - 1, v0 = base.v0, r_near = base.r_near;
    const double lines_per_slope = side.lines_per_slope, j_lo = side.j_lo;
    detail::RadialGroup g = base;
    for (int l = 0; l < detail::kRadialLanes; ++l) {
      const int line = group * detail::kRadialLanes + l;
      if (line >= side.lines) continue;  // first == end == 0
      const double m = (j_lo + line) / lines_per_slope;
      g.m[l] = m;
      g.inv_metres[l] = static_cast<float>(1 / (std::sqrt(1 + m * m) * f.cell_size));
      const int columns =
          side.line_end.empty() ? side.columns : side.line_end[static_cast<std::size_t>(line)];
      // Columns whose point v = v0 + (r_near + k) m lies in [0, size_v - 1] (within 1e-5).
      double k_min = 0, k_max = columns - 1;
      if (m != 0) {
        const double k_a = (-1e-5 - v0) / m - r_near, k_b = (v_max + 1e-5 - v0) / m - r_near;
        k_min = std::max(k_min, std::ceil(std::min(k_a, k_b)));
        k_max = std::min(k_max, std::floor(std::max(k_a, k_b)));
      } else if (!(v0 > -1e-5 && v0 < v_max + 1e-5)) {
        k_max = -1;
      }
      g.first[l] = static_cast<int>(std::min(k_min, static_cast<double>(columns)));
      g.end[l] = std::max(g.first[l], static_cast<int>(k_max) + 1);
      g.width = std::max(g.width, columns);
    }
    return g;
  };
  auto block_of = [&](int index, int group) {
    return sides_[index].angle.data() +
           static_cast<std::size_t>(group) * detail::kRadialLanes * sides_[index].columns;
  };
  // Slopes to angles; -inf (nothing in between) gives -pi/2, NaN stays NaN.
  auto to_angles = [](float* block, const detail::RadialGroup& g) {
    detail::fast_atan_array(block, static_cast<std::size_t>(g.width) * detail::kRadialLanes);
  };
  // Groups 2 u and 2 u + 1 of side `index`: one walk of sixteen lanes where the AVX-512 copy
  // runs (sweep_radial_pair_lanes). A group past the side's last line, or serving no region,
  // has width 0 and is not written.
  auto sweep_pair = [&](int index, int u, detail::RadialScratch& scratch) {
    const int groups = (sides_[index].lines + detail::kRadialLanes - 1) / detail::kRadialLanes;
    const detail::RadialGroup a = group_of(index, 2 * u), b = group_of(index, 2 * u + 1);
    if (a.width == 0 && b.width == 0) return;
    float* block_a = block_of(index, 2 * u);
    float* block_b = 2 * u + 1 < groups ? block_of(index, 2 * u + 1) : nullptr;
    detail::sweep_radial_pair_lanes(a, b, scratch, block_a, block_b);
    to_angles(block_a, a);
    if (block_b) to_angles(block_b, b);
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, pair_start[4]),
                    [&](const tbb::blocked_range<int>& range) {
                      thread_local detail::RadialScratch scratch;
                      int index = 0;
                      for (int at = range.begin(); at < range.end(); ++at) {
                        while (at >= pair_start[index + 1]) ++index;
                        sweep_pair(index, at - pair_start[index], scratch);
                      }
                    });
}

float RadialHorizonSweep::horizon(int x, int y) const {
  const float rx = static_cast<float>(x) - foot_.x, ry = static_cast<float>(y) - foot_.y;
  if (rx == 0 && ry == 0) return -kHalfPi;
  const int index = std::fabs(rx) >= std::fabs(ry) ? (rx > 0 ? 0 : 1) : (ry > 0 ? 2 : 3);
  const Side& side = sides_[index];
  if (side.lines == 0) return -kHalfPi;
  const int u = side.x_major ? x : y;
  const float ru = std::fabs(side.x_major ? rx : ry), rv = side.x_major ? ry : rx;
  // Explicit multiply-adds here and in horizons8, so that both give the same floats.
  const float jf = std::fma(rv / ru, side.lines_per_slope, -static_cast<float>(side.j_lo));
  const int l0 = std::clamp(static_cast<int>(std::floor(jf)), 0, std::max(side.lines - 2, 0));
  const float t = side.lines > 1 ? std::clamp(jf - static_cast<float>(l0), 0.0f, 1.0f) : 0.0f;
  const int k = side.sign * (u - side.u_first);
  if (k < 0 || k >= side.columns) return -kHalfPi;
  const float lo = side.at(l0, k), hi = side.lines > 1 ? side.at(l0 + 1, k) : lo;
  if (std::isnan(lo) || std::isnan(hi)) {
    // A line beside the texel is outside the field here. With F outside, the texel's own ray
    // may leave the field where its neighbour line does not (grazing the border): exact ray.
    if (!foot_inside_) {
      const glm::vec2 r = foot_ - glm::vec2(x, y);
      return ray_horizon(*field_, height_scale_, glm::vec2(x, y), height_scale_ * field_->at(x, y),
                         std::atan2(r.y, r.x), std::sqrt(glm::dot(r, r)) * field_->cell_size,
                         false);
    }
    return std::isnan(lo) ? (std::isnan(hi) ? -kHalfPi : hi) : lo;
  }
  return std::fma(t, hi - lo, lo);
}

void RadialHorizonSweep::horizons16(int x0, int y, float* out) const {
#ifdef __AVX2__
  if (detail::sweep_isa() == detail::SweepIsa::kAvx512) {
    // Each side the run reaches (at most two: +x or -x where |rx| >= |ry| at an end, +y or -y by
    // ry's sign where |rx| < |ry| somewhere), then horizon() for the lanes none of them answered
    // (the foot's texel, columns past a side, NaN lines).
    const float ry = static_cast<float>(y) - foot_.y, ary = std::fabs(ry);
    const float rx0 = static_cast<float>(x0) - foot_.x,
                rx15 = static_cast<float>(x0 + 15) - foot_.x;
    const bool y_side = std::min(std::fabs(rx0), std::fabs(rx15)) < ary || (rx0 < 0 && rx15 > 0);
    const bool reaches[4] = {rx15 > 0 && rx15 >= ary, rx0 < 0 && -rx0 >= ary, y_side && ry > 0,
                             y_side && ry < 0};
    unsigned done = 0;
    for (int index = 0; index < 4; ++index) {
      const Side& side = sides_[index];
      if (!reaches[index] || side.lines < 2) continue;
      const detail::RadialSideView view{side.angle.data(), side.columns,        side.lines,
                                        side.j_lo,         side.u_first,        side.sign,
                                        side.x_major,      side.lines_per_slope};
      done |= detail::avx512::radial_horizons16(view, index, foot_.x, foot_.y, x0, y, out);
    }
    for (int l = 0; l < 16; ++l)
      if (!(done >> l & 1u)) out[l] = horizon(x0 + l, y);
    return;
  }
#endif
  horizons8(x0, y, out);
  horizons8(x0 + 8, y, out + 8);
}

void RadialHorizonSweep::horizons8(int x0, int y, float* out) const {
#ifdef __AVX2__
  // The vector path needs all eight texels on one side of F, between two lines inside the field.
  const float ry = static_cast<float>(y) - foot_.y;
  const float rx0 = static_cast<float>(x0) - foot_.x, rx7 = static_cast<float>(x0 + 7) - foot_.x;
  int index = -1;
  if (rx0 > 0 && rx0 >= std::fabs(ry))
    index = 0;
  else if (rx7 < 0 && -rx7 >= std::fabs(ry))
    index = 1;
  else if (std::fabs(rx0) < std::fabs(ry) && std::fabs(rx7) < std::fabs(ry))
    index = ry > 0 ? 2 : 3;
  if (index >= 0 && sides_[index].lines >= 2) {
    const Side& side = sides_[index];
    const __m256 rx =
        _mm256_sub_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(
                          _mm256_set1_epi32(x0), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7))),
                      _mm256_set1_ps(foot_.x));
    const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256 ru = side.x_major ? _mm256_and_ps(rx, abs_mask) : _mm256_set1_ps(std::fabs(ry));
    const __m256 rv = side.x_major ? _mm256_set1_ps(ry) : rx;
    const __m256 jf = _mm256_fmadd_ps(_mm256_div_ps(rv, ru), _mm256_set1_ps(side.lines_per_slope),
                                      _mm256_set1_ps(-static_cast<float>(side.j_lo)));
    const __m256i l0 = _mm256_min_epi32(
        _mm256_max_epi32(_mm256_cvttps_epi32(_mm256_floor_ps(jf)), _mm256_setzero_si256()),
        _mm256_set1_epi32(side.lines - 2));
    const __m256 t =
        _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(jf, _mm256_cvtepi32_ps(l0)), _mm256_setzero_ps()),
                      _mm256_set1_ps(1.0f));
    const __m256i k =
        side.x_major
            ? _mm256_mullo_epi32(
                  _mm256_set1_epi32(side.sign),
                  _mm256_sub_epi32(_mm256_add_epi32(_mm256_set1_epi32(x0),
                                                    _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)),
                                   _mm256_set1_epi32(side.u_first)))
            : _mm256_set1_epi32(side.sign * (y - side.u_first));
    const __m256i in_range =
        _mm256_andnot_si256(_mm256_cmpgt_epi32(_mm256_setzero_si256(), k),
                            _mm256_cmpgt_epi32(_mm256_set1_epi32(side.columns), k));
    if (_mm256_movemask_ps(_mm256_castsi256_ps(in_range)) == 0xff) {
      // at(line, k) = angle[((line >> 3) columns + k) 8 + (line & 7)]
      auto slot = [&](__m256i line) {
        return _mm256_add_epi32(
            _mm256_slli_epi32(_mm256_add_epi32(_mm256_mullo_epi32(_mm256_srli_epi32(line, 3),
                                                                  _mm256_set1_epi32(side.columns)),
                                               k),
                              3),
            _mm256_and_si256(line, _mm256_set1_epi32(7)));
      };
      const __m256 lo = _mm256_i32gather_ps(side.angle.data(), slot(l0), 4);
      const __m256 hi = _mm256_i32gather_ps(side.angle.data(),
                                            slot(_mm256_add_epi32(l0, _mm256_set1_epi32(1))), 4);
      const __m256 nan =
          _mm256_or_ps(_mm256_cmp_ps(lo, lo, _CMP_UNORD_Q), _mm256_cmp_ps(hi, hi, _CMP_UNORD_Q));
      if (_mm256_testz_ps(nan, nan)) {
        _mm256_storeu_ps(out, _mm256_fmadd_ps(t, _mm256_sub_ps(hi, lo), lo));
        return;
      }
    }
  }
#endif
  for (int l = 0; l < 8; ++l) out[l] = horizon(x0 + l, y);
}

}  // namespace penumbra::terrain_shadow
