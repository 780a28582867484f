// Cap-vs-horizon shading of one spherical light: single-direction pyramid march, radial line
// sweep from the light's foot, and the cap's cosine-weighted visible solid angle (see
// light_horizon.h).
#include "penumbra/systems/terrain_shadow/light_horizon.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "fast_atan.h"
#include "penumbra/systems/terrain_shadow/horizon_sweep.h"
#include "sweep_geometry.h"

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace penumbra::terrain_shadow {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kHalfPi = kPi / 2;

// asin and acos through fast_atan (1.1e-7 rad): |x| <= 1; +-1 give +-pi/2 (x / 0 = +-inf).
inline float fast_asin(float x) {
  return detail::fast_atan(x / std::sqrt(std::max((1 - x) * (1 + x), 0.0f)));
}
inline float fast_acos(float x) {
  return kHalfPi - fast_asin(x);
}

// Uniform cubic B-spline at a knot and at the mid-point after it ([Meier13] eq. 4.8-4.12, sec. 5.2).
inline float knot_value(float am, float a0, float a1) {
  return (am + 4 * a0 + a1) * (1.0f / 6);
}
inline float mid_value(float am, float a0, float a1, float a2) {
  return (am + 23 * (a0 + a1) + a2) * (1.0f / 48);
}

// tau_j of cap_horizon_direction for count 1..kMaxCapHorizons, ascending.
struct HorizonNodes {
  std::array<std::array<float, kMaxCapHorizons>, kMaxCapHorizons + 1> tau{};
  HorizonNodes() {
    for (int count = 1; count <= kMaxCapHorizons; ++count)
      for (int j = 0; j < count; ++j)
        tau[count][j] = static_cast<float>(-std::cos(std::numbers::pi * (j + 1) / (count + 1)));
  }
};
const HorizonNodes& nodes() {
  static const HorizonNodes n;  // initialised on first use, thread-safe
  return n;
}

}  // namespace

LightHorizonMarch::LightHorizonMarch(const HeightPyramid& pyramid, const MarchParams& march)
    : pyramid_(&pyramid) {
  const std::string name = pyramid.source().empty() ? "height field" : pyramid.source();
  if (pyramid.levels() == 0)
    throw std::invalid_argument(name + ": light horizon march: the pyramid has not been built");
  if (!(march.level_offset >= 0) || !std::isfinite(march.level_offset))
    throw std::invalid_argument(name + ": light horizon march: level offset " +
                                std::to_string(march.level_offset) + " must be finite and >= 0");
  const int n = pyramid.levels();
  const double sr = std::exp2(1.0 / pyramid.level_step());
  const double shift = pyramid.level_step() * static_cast<double>(march.level_offset);
  double di = 1, spacing = 1;
  for (int i = 0; i < n; ++i) {
    d_.push_back(static_cast<float>(di));
    inv_metres_.push_back(static_cast<float>(1.0 / (di * pyramid.cell_size())));
    // Eq. 4.14 with level 0 the finest (horizon_march.h).
    level_.push_back(
        pyramid.level_data(std::clamp(static_cast<int>(std::ceil(i - shift - 1e-9)), 0, n - 1)));
    di += spacing;
    spacing *= sr;
  }
}

float LightHorizonMarch::horizon(int x, int y, glm::vec2 dir, float limit) const {
  const int n = samples();
  // Eq. 4.24: samples up to the first one beyond the light; reach: the light as a spline
  // parameter (knot i at d_i, linear in between).
  const int beyond = static_cast<int>(std::upper_bound(d_.begin(), d_.end(), limit) - d_.begin());
  if (beyond == 0) return -kHalfPi;
  const int last = std::min(beyond, n - 1);
  const float reach = beyond == n ? static_cast<float>(n - 1)
                                  : static_cast<float>(beyond - 1) +
                                        (limit - d_[beyond - 1]) / (d_[beyond] - d_[beyond - 1]);
  const int w = pyramid_->width(), h = pyramid_->height();
  const float h0 = pyramid_->level_data(0)[static_cast<std::size_t>(y) * w + x];
  constexpr int kStack = 128;
  std::array<float, kStack> stack;
  std::vector<float> heap;
  float* a = stack.data();
  if (last + 1 > kStack) {
    heap.resize(static_cast<std::size_t>(last) + 1);
    a = heap.data();
  }
  int count = 0;
  for (int i = 0; i <= last; ++i) {
    int ox, oy;
    float fx, fy;
    detail::split_offset(d_[i] * dir.x, ox, fx);
    detail::split_offset(d_[i] * dir.y, oy, fy);
    const int sx = fx > 0 ? 1 : 0, sy = fy > 0 ? 1 : 0;
    const int px = x + ox, py = y + oy;
    // Footprints outside the field are dropped; rays are straight, so the rest are too.
    if (px < 0 || py < 0 || px + sx > w - 1 || py + sy > h - 1) break;
    const float* r0 = level_[i] + static_cast<std::size_t>(py) * w + px;
    const float* r1 = r0 + static_cast<std::size_t>(sy) * w;
    const float top = r0[0] + fx * (r0[sx] - r0[0]);
    const float bottom = r1[0] + fx * (r1[sx] - r1[0]);
    a[count++] = (top + fy * (bottom - top) - h0) * inv_metres_[i];  // eq. 4.5-4.6
  }
  if (count == 0) return -kHalfPi;
  detail::fast_atan_array(a, static_cast<std::size_t>(count));
  auto at = [&](int i) { return a[std::clamp(i, 0, count - 1)]; };
  // Eq. 4.13 and 4.25: the spline's maximum over knots and mid-points up to the light.
  float best = -std::numeric_limits<float>::infinity();
  for (int i = 0; i < count; ++i) {
    if (static_cast<float>(i) <= reach)
      best = std::max(best, knot_value(at(i - 1), at(i), at(i + 1)));
    if (i + 1 < count && i + 0.5f <= reach)
      best = std::max(best, mid_value(at(i - 1), at(i), at(i + 1), at(i + 2)));
  }
  if (reach > 0 && reach < static_cast<float>(count - 1)) {  // the spline at the light itself
    const int j = static_cast<int>(reach);
    const float t = reach - static_cast<float>(j), t2 = t * t, t3 = t2 * t;
    const float wt[4] = {(1 - t) * (1 - t) * (1 - t) / 6, (3 * t3 - 6 * t2 + 4) / 6,
                         (-3 * t3 + 3 * t2 + 3 * t + 1) / 6, t3 / 6};  // eq. 4.9-4.12
    float v = 0;
    for (int q = 0; q < 4; ++q) v += wt[q] * at(j - 1 + q);
    best = std::max(best, v);
  }
  return best == -std::numeric_limits<float>::infinity() ? -kHalfPi : best;
}

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

void RadialHorizonSweep::run(const assets::HeightField& f, float height_scale, glm::vec2 foot,
                             float reach, std::span<const TexelRect> regions) {
  field_ = &f;
  height_scale_ = height_scale;
  foot_ = foot / f.cell_size;
  foot_inside_ = foot_.x >= 0 && foot_.y >= 0 && foot_.x <= static_cast<float>(f.width - 1) &&
                 foot_.y <= static_cast<float>(f.height - 1);
  for (int index = 0; index < 4; ++index) {
    Side& side = sides_[index];
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
    side.angle.resize(static_cast<std::size_t>(side.lines) * side.columns);
    side.line_end.clear();
    if (!regions.empty()) limit_lines(side, regions);
    const std::size_t stride_u = side.x_major ? 1 : static_cast<std::size_t>(f.width);
    const std::size_t stride_v = side.x_major ? static_cast<std::size_t>(f.width) : 1;
    const float* heights = f.heights.data();
    const double v_max = size_v - 1;
    tbb::parallel_for(
        tbb::blocked_range<int>(0, side.lines, 8), [&](const tbb::blocked_range<int>& range) {
          std::vector<float> hull_r(static_cast<std::size_t>(side.columns)),
              hull_h(static_cast<std::size_t>(side.columns));
          for (int line = range.begin(); line < range.end(); ++line) {
            const double m = (j_lo + line) / lines_per_slope;
            const float inv_metres = static_cast<float>(1 / (std::sqrt(1 + m * m) * f.cell_size));
            float* out = side.angle.data() + static_cast<std::size_t>(line) * side.columns;
            const int columns = side.line_end.empty()
                                    ? side.columns
                                    : side.line_end[static_cast<std::size_t>(line)];
            if (columns == 0) continue;
            // Columns whose point v = v0 + (r_near + k) m lies in [0, size_v - 1] (within 1e-5).
            double k_min = 0, k_max = columns - 1;
            if (m != 0) {
              const double k_a = (-1e-5 - v0) / m - r_near, k_b = (v_max + 1e-5 - v0) / m - r_near;
              k_min = std::max(k_min, std::ceil(std::min(k_a, k_b)));
              k_max = std::min(k_max, std::floor(std::max(k_a, k_b)));
            } else if (!(v0 > -1e-5 && v0 < v_max + 1e-5)) {
              k_max = -1;
            }
            const int first = static_cast<int>(std::min(k_min, static_cast<double>(columns)));
            const int end = std::max(first, static_cast<int>(k_max) + 1);
            std::fill(out, out + first, std::numeric_limits<float>::quiet_NaN());
            std::fill(out + end, out + columns, std::numeric_limits<float>::quiet_NaN());
            float* hr = hull_r.data();
            float* hh = hull_h.data();
            int n = 0;
            for (int k = first; k < end; ++k) {
              const double r = r_near + k;
              const double v = v0 + r * m;
              int vi = static_cast<int>(std::floor(v));
              float fv = static_cast<float>(v - vi);
              if (fv > 1 - 1e-5f) {
                ++vi;
                fv = 0;
              }
              if (vi < 0 || vi >= size_v - 1) {  // on the border line (within 1e-5)
                vi = std::clamp(vi, 0, size_v - 1);
                fv = 0;
              }
              const float* sample =
                  heights + static_cast<std::size_t>(side.u_first + side.sign * k) * stride_u +
                  static_cast<std::size_t>(vi) * stride_v;
              const float h =
                  height_scale * (sample[0] + fv * (sample[fv > 0 ? stride_v : 0] - sample[0]));
              const float rf = static_cast<float>(r);
              // The tangent from (r, h) to the upper hull of the samples between it and F.
              while (n >= 2 &&
                     (hh[n - 1] - h) * (rf - hr[n - 2]) <= (hh[n - 2] - h) * (rf - hr[n - 1]))
                --n;
              out[k] = n > 0 ? (hh[n - 1] - h) / (rf - hr[n - 1]) * inv_metres
                             : -std::numeric_limits<float>::infinity();
              hr[n] = rf;
              hh[n] = h;
              ++n;
            }
            if (end > first)  // slopes to angles; -inf (nothing in between) gives -pi/2
              detail::fast_atan_array(out + first, static_cast<std::size_t>(end - first));
          }
        });
  }
}

float RadialHorizonSweep::horizon(int x, int y) const {
  const float rx = static_cast<float>(x) - foot_.x, ry = static_cast<float>(y) - foot_.y;
  if (rx == 0 && ry == 0) return -kHalfPi;
  const int index = std::fabs(rx) >= std::fabs(ry) ? (rx > 0 ? 0 : 1) : (ry > 0 ? 2 : 3);
  const Side& side = sides_[index];
  if (side.lines == 0) return -kHalfPi;
  const int u = side.x_major ? x : y;
  const float ru = std::fabs(side.x_major ? rx : ry), rv = side.x_major ? ry : rx;
  const float jf = rv / ru * side.lines_per_slope - static_cast<float>(side.j_lo);
  const int l0 = std::clamp(static_cast<int>(std::floor(jf)), 0, std::max(side.lines - 2, 0));
  const float t = side.lines > 1 ? std::clamp(jf - static_cast<float>(l0), 0.0f, 1.0f) : 0.0f;
  const int k = side.sign * (u - side.u_first);
  if (k < 0 || k >= side.columns) return -kHalfPi;
  const float* a = side.angle.data() + static_cast<std::size_t>(l0) * side.columns + k;
  const float lo = a[0], hi = side.lines > 1 ? a[side.columns] : lo;
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
  return lo + t * (hi - lo);
}

bool make_light_cap(const glm::vec3& d, float radius, LightCap& cap) {
  if (!(radius > 0) || !std::isfinite(radius)) return false;
  const float dist = std::sqrt(glm::dot(d, d));
  if (!std::isfinite(dist) || !(dist > radius)) return false;
  cap.dir = d / dist;
  cap.rho = radius / dist;
  cap.cos_half = std::sqrt((dist - radius) * (dist + radius)) / dist;
  const float plane = std::sqrt(d.x * d.x + d.y * d.y);
  cap.plane_distance = plane;
  cap.cos_e = plane / dist;
  cap.sin_e = d.z / dist;
  cap.plane_dir = plane > 0 ? glm::vec2(d.x, d.y) / plane : glm::vec2(1.0f, 0.0f);
  return true;
}

glm::vec2 cap_horizon_direction(const LightCap& cap, int j, int count) {
  const float s = cap.rho * nodes().tau[count][j];
  const glm::vec2 side(-cap.plane_dir.y, cap.plane_dir.x);
  const glm::vec2 v = std::sqrt(1 - s * s) * cap.cos_e * cap.plane_dir + s * side;
  const float len = std::sqrt(glm::dot(v, v));
  return len > 1e-12f ? v / len : cap.plane_dir;
}

namespace {

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

// Chord nodes of cap_transfer for 1..kMaxStrips strips: cos and sin of psi_j.
constexpr int kMaxStrips = kMaxCapStrips;
struct StripNodes {
  std::vector<float> cos_psi, sin_psi;  // strips s at offset s (s - 1) / 2
  StripNodes() {
    for (int strips = 1; strips <= kMaxStrips; ++strips)
      for (int j = 0; j < strips; ++j) {
        const double psi = (j + 0.5) * std::numbers::pi / strips;
        cos_psi.push_back(static_cast<float>(std::cos(psi)));
        sin_psi.push_back(static_cast<float>(std::sin(psi)));
      }
  }
  static std::size_t offset(int strips) {
    return static_cast<std::size_t>(strips) * (strips - 1) / 2;
  }
};
const StripNodes& strip_nodes() {
  static const StripNodes n;
  return n;
}

// Everything cap_transfer's chord loops share.
struct CapFrame {
  float rho, nc, ns, nu, sin_e, cos_e;
  int strips;
  const float* cos_psi;  // per chord: s = rho cos(psi), half-length rho sin(psi)
  const float* sin_psi;
  const float* horizon;  // per chord: sine of the horizon elevation
};

// Chords of a cap wholly in front of the tangent plane, in u (see the header): the horizon
// bounds u by square roots alone and the chord integral of (n.w) / c0 du is
//   nc (hi - lo) + ns s (asin(hi / sq) - asin(lo / sq)) + nu (c0(lo) - c0(hi)),
// c0(u) = sqrt(q - u^2), q = 1 - s^2, sq = sqrt(q). Eight chords at a time (AVX2, with a scalar
// fallback doing the same operations); padding chords have zero length and weight.
float front_chords(const CapFrame& f) {
  constexpr int kLanes = 8;
  const int m = f.strips, padded = (m + kLanes - 1) / kLanes * kLanes;
  // Only [0, padded) is ever written or read (no zero-fill: it would cost more than the maths).
  alignas(32) std::array<float, kMaxStrips> c, sn, a, lo, hi, cl, ch;
  alignas(32) std::array<float, 2 * kMaxStrips> y;
  for (int j = 0; j < padded; ++j) {
    const bool real = j < m;
    c[j] = real ? f.cos_psi[j] : 0.0f;
    sn[j] = real ? f.sin_psi[j] : 0.0f;
    a[j] = real ? f.horizon[j] : -1.0f;
  }
  const bool below = f.sin_e<0, above = f.sin_e> 0;
#ifdef __AVX2__
  const __m256 rho = _mm256_set1_ps(f.rho), one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 sin_e = _mm256_set1_ps(f.sin_e), cos_e = _mm256_set1_ps(f.cos_e);
  const __m256 tiny = _mm256_set1_ps(1e-30f), sign = _mm256_set1_ps(-0.0f);
  const __m256 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
  for (int j = 0; j < padded; j += kLanes) {
    const __m256 s = _mm256_mul_ps(rho, _mm256_load_ps(c.data() + j));
    const __m256 h = _mm256_mul_ps(rho, _mm256_load_ps(sn.data() + j));
    const __m256 aj = _mm256_load_ps(a.data() + j);
    const __m256 q = _mm256_fnmadd_ps(s, s, one), r = _mm256_sqrt_ps(q);
    // w_z = c0 sin_e + u cos_e > a; boundaries u = a cos_e -+ sqrt(q - a^2) sin_e.
    const __m256 root = _mm256_sqrt_ps(_mm256_max_ps(_mm256_fnmadd_ps(aj, aj, q), zero));
    const __m256 base = _mm256_mul_ps(aj, cos_e);
    const __m256 lower = _mm256_fnmadd_ps(root, sin_e, base);
    const __m256 upper = _mm256_fmadd_ps(root, sin_e, base);
    const __m256 cr = _mm256_mul_ps(cos_e, r);
    const __m256 valid = _mm256_cmp_ps(aj, _mm256_xor_ps(r, sign), _CMP_GT_OQ);
    const __m256 lower_on =
        _mm256_and_ps(valid, below ? all : _mm256_cmp_ps(aj, _mm256_xor_ps(cr, sign), _CMP_GT_OQ));
    const __m256 upper_on = _mm256_and_ps(valid, above ? _mm256_cmp_ps(aj, cr, _CMP_GT_OQ) : zero);
    const __m256 hidden = _mm256_or_ps(_mm256_cmp_ps(aj, r, _CMP_GE_OQ),
                                       above ? zero : _mm256_cmp_ps(aj, cr, _CMP_GE_OQ));
    const __m256 neg_h = _mm256_xor_ps(h, sign);
    const __m256 l = _mm256_max_ps(neg_h, _mm256_blendv_ps(neg_h, lower, lower_on));
    __m256 u = _mm256_min_ps(h, _mm256_blendv_ps(h, upper, upper_on));
    u = _mm256_blendv_ps(_mm256_max_ps(u, l), l, hidden);
    const __m256 c_lo = _mm256_sqrt_ps(_mm256_max_ps(_mm256_fnmadd_ps(l, l, q), zero));
    const __m256 c_hi = _mm256_sqrt_ps(_mm256_max_ps(_mm256_fnmadd_ps(u, u, q), zero));
    _mm256_store_ps(lo.data() + j, l);
    _mm256_store_ps(hi.data() + j, u);
    _mm256_store_ps(cl.data() + j, c_lo);
    _mm256_store_ps(ch.data() + j, c_hi);
    // asin(v / sq) = atan(v / c0(v)).
    _mm256_store_ps(y.data() + j, _mm256_div_ps(l, _mm256_max_ps(c_lo, tiny)));
    _mm256_store_ps(y.data() + padded + j, _mm256_div_ps(u, _mm256_max_ps(c_hi, tiny)));
  }
#else
  for (int j = 0; j < padded; ++j) {
    const float s = f.rho * c[j], h = f.rho * sn[j], aj = a[j];
    const float q = 1 - s * s, r = std::sqrt(q);
    const float root = std::sqrt(std::max(q - aj * aj, 0.0f));
    const float lower = aj * f.cos_e - root * f.sin_e, upper = aj * f.cos_e + root * f.sin_e;
    const float cr = f.cos_e * r;
    const bool valid = aj > -r;
    const bool lower_on = valid && (below || aj > -cr);
    const bool upper_on = valid && above && aj > cr;
    const bool hidden = aj >= r || (!above && aj >= cr);
    const float l = std::max(-h, lower_on ? lower : -h);
    float u = std::min(h, upper_on ? upper : h);
    u = hidden ? l : std::max(u, l);
    lo[j] = l;
    hi[j] = u;
    cl[j] = std::sqrt(std::max(q - l * l, 0.0f));
    ch[j] = std::sqrt(std::max(q - u * u, 0.0f));
    y[j] = l / std::max(cl[j], 1e-30f);
    y[padded + j] = u / std::max(ch[j], 1e-30f);
  }
#endif
  detail::fast_atan_array(y.data(), static_cast<std::size_t>(2 * padded));
  float sum = 0;
  for (int j = 0; j < padded; ++j) {
    const float s = f.rho * c[j];
    // c0(lo) - c0(hi) in product form: tiny caps keep their precision.
    const float dc = (hi[j] - lo[j]) * (hi[j] + lo[j]) / std::max(cl[j] + ch[j], 1e-30f);
    sum += sn[j] * (f.nc * (hi[j] - lo[j]) + f.ns * s * (y[padded + j] - y[j]) + f.nu * dc);
  }
  return sum;
}

// Any cap, including one the tangent plane cuts: chords in t (u = sq sin t, du / c0 = dt),
// bounded by the horizon (sin(e + t) > a / sq) and the tangent plane (sq r0 cos(t - phase) +
// ns s > 0), each piece integrated as sq (nc sin t - nu cos t) + ns s t.
float general_chords(const CapFrame& f) {
  const float e = std::atan2(f.sin_e, f.cos_e);
  const float r0 = std::sqrt(f.nc * f.nc + f.nu * f.nu), phase = std::atan2(f.nu, f.nc);
  auto chord = [&](float r, float s, float lo, float hi) {
    const float m = (hi + lo) / 2, half = (hi - lo) / 2;
    return 2 * r * std::sin(half) * (f.nc * std::cos(m) + f.nu * std::sin(m)) +
           f.ns * s * (hi - lo);
  };
  float sum = 0;
  for (int j = 0; j < f.strips; ++j) {
    const float s = f.rho * f.cos_psi[j], h = f.rho * f.sin_psi[j];
    const float r = std::sqrt(1 - s * s);
    const float t_max = fast_asin(std::min(h / r, 1.0f));
    float lo = -t_max, hi = t_max;
    const float ratio = f.horizon[j] / r;
    if (ratio >= 1) continue;  // the whole chord is below the horizon
    if (ratio > -1) {
      const float as = fast_asin(ratio);  // e + t in (as, pi - as)
      lo = std::max(lo, as - e);
      hi = std::min(hi, kPi - as - e);
    }
    if (!(lo < hi)) continue;
    float part = 0;
    if (!(r0 * r > 0)) {
      if (f.ns * s > 0) part = chord(r, s, lo, hi);
    } else {
      const float b = -f.ns * s / (r0 * r);  // in front: cos(t - phase) > b
      if (b <= -1) {
        part = chord(r, s, lo, hi);
      } else if (b < 1) {
        const float width = fast_acos(b);
        for (int k = -1; k <= 1; ++k) {
          const float centre = phase + 2 * kPi * static_cast<float>(k);
          const float l = std::max(lo, centre - width), u = std::min(hi, centre + width);
          if (l < u) part += chord(r, s, l, u);
        }
      }
    }
    sum += f.sin_psi[j] * part;
  }
  return sum;
}

}  // namespace

float cap_transfer(const LightCap& cap, const glm::vec3& n, const float* horizon, int count,
                   int strips) {
  const float rho = cap.rho;
  const glm::vec3 side(-cap.plane_dir.y, cap.plane_dir.x, 0.0f);
  const glm::vec3 up(-cap.sin_e * cap.plane_dir.x, -cap.sin_e * cap.plane_dir.y, cap.cos_e);
  const float nc = glm::dot(n, cap.dir);
  if (nc <= -rho) return 0;  // wholly behind the tangent plane

  // Sines of the horizon samples, and the cap's lowest and highest elevation (sines).
  std::array<float, kMaxCapHorizons> sh{};
  float lowest = 1, highest = -1;
  for (int j = 0; j < count; ++j) {
    sh[j] = fast_sin(std::clamp(horizon[j], -kHalfPi, kHalfPi));
    lowest = std::min(lowest, sh[j]);
    highest = std::max(highest, sh[j]);
  }
  const bool pole = rho > cap.cos_e;  // the cap contains the zenith or the nadir
  const float bottom = pole && cap.sin_e < 0 ? -1 : cap.sin_e * cap.cos_half - cap.cos_e * rho;
  const float top = pole && cap.sin_e > 0 ? 1 : cap.sin_e * cap.cos_half + cap.cos_e * rho;
  if (lowest >= top) return 0;  // the horizon hides the whole cap
  const bool open = highest <= bottom;
  if (open && nc >= rho) return kPi * rho * rho * nc;  // exact: the whole cap, all in front

  strips = std::clamp(strips, 1, kMaxStrips);
  const std::size_t at = StripNodes::offset(strips);
  CapFrame f{rho,
             nc,
             glm::dot(n, side),
             glm::dot(n, up),
             cap.sin_e,
             cap.cos_e,
             strips,
             strip_nodes().cos_psi.data() + at,
             strip_nodes().sin_psi.data() + at,
             nullptr};
  // The horizon along each chord: linear in tau = cos(psi) between the samples (open: -1).
  std::array<float, kMaxStrips> chord_horizon;
  const float* tau = nodes().tau[count].data();
  for (int j = 0; j < strips; ++j) {
    float a = sh[0];
    if (count > 1) {
      const float c = f.cos_psi[j];
      int k = 0;
      while (k + 2 < count && c > tau[k + 1]) ++k;
      const float w = std::clamp((c - tau[k]) / (tau[k + 1] - tau[k]), 0.0f, 1.0f);
      a = sh[k] + w * (sh[k + 1] - sh[k]);
    }
    chord_horizon[j] = open ? -1.0f : a;
  }
  f.horizon = chord_horizon.data();
  const float sum = nc >= rho ? front_chords(f) : general_chords(f);
  return std::max(sum * rho * kPi / static_cast<float>(strips), 0.0f);
}

}  // namespace penumbra::terrain_shadow
