#include "penumbra/systems/terrain_shadow/cap_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "fast_math.h"

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace penumbra::terrain_shadow {
namespace {

using detail::kHalfPi;
using detail::kPi;

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

// Chord nodes of cap_transfer for 1..kMaxStrips strips: cos and sin of psi_j, each count's
// block padded with zeros to a multiple of kLanes (a padding chord has zero length and weight).
constexpr int kMaxStrips = kMaxCapStrips;
constexpr int kLanes = 8;
constexpr int padded(int strips) {
  return (strips + kLanes - 1) / kLanes * kLanes;
}
struct StripNodes {
  std::vector<float> cos_psi, sin_psi;
  std::array<std::size_t, kMaxStrips + 1> offsets{};
  StripNodes() {
    for (int strips = 1; strips <= kMaxStrips; ++strips) {
      offsets[strips] = cos_psi.size();
      for (int j = 0; j < padded(strips); ++j) {
        const double psi = (j + 0.5) * std::numbers::pi / strips;
        cos_psi.push_back(j < strips ? static_cast<float>(std::cos(psi)) : 0.0f);
        sin_psi.push_back(j < strips ? static_cast<float>(std::sin(psi)) : 0.0f);
      }
    }
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
  const float* cos_psi;  // per chord: s = rho cos(psi), half-length rho sin(psi); padded
  const float* sin_psi;
  const float* horizon;  // per chord: sine of the horizon elevation; padded with -1
};

#ifdef __AVX2__
// The bounds [lo, hi] in u of eight chords (lanes) above the horizon sine a and inside the cap
// (|u| <= h), with c0 = sqrt(q - u^2) at both ends: w_z = c0 sin_e + u cos_e > a bounds u at
// a cos_e -+ sqrt(q - a^2) sin_e. `below` / `above`: sin_e < 0 / > 0 (masks).
struct ChordBounds {
  __m256 lo, hi, c_lo, c_hi;
};
inline ChordBounds chord_bounds8(__m256 a, __m256 q, __m256 h, __m256 sin_e, __m256 cos_e,
                                 __m256 below, __m256 above) {
  const __m256 zero = _mm256_setzero_ps(), sign = _mm256_set1_ps(-0.0f);
  const __m256 r = _mm256_sqrt_ps(q);
  const __m256 root = _mm256_sqrt_ps(_mm256_max_ps(_mm256_fnmadd_ps(a, a, q), zero));
  const __m256 base = _mm256_mul_ps(a, cos_e);
  const __m256 lower = _mm256_fnmadd_ps(root, sin_e, base);
  const __m256 upper = _mm256_fmadd_ps(root, sin_e, base);
  const __m256 cr = _mm256_mul_ps(cos_e, r);
  const __m256 valid = _mm256_cmp_ps(a, _mm256_xor_ps(r, sign), _CMP_GT_OQ);
  const __m256 lower_on = _mm256_and_ps(
      valid, _mm256_or_ps(below, _mm256_cmp_ps(a, _mm256_xor_ps(cr, sign), _CMP_GT_OQ)));
  const __m256 upper_on =
      _mm256_and_ps(_mm256_and_ps(valid, above), _mm256_cmp_ps(a, cr, _CMP_GT_OQ));
  const __m256 hidden = _mm256_or_ps(_mm256_cmp_ps(a, r, _CMP_GE_OQ),
                                     _mm256_andnot_ps(above, _mm256_cmp_ps(a, cr, _CMP_GE_OQ)));
  const __m256 neg_h = _mm256_xor_ps(h, sign);
  ChordBounds b;
  b.lo = _mm256_max_ps(neg_h, _mm256_blendv_ps(neg_h, lower, lower_on));
  b.hi = _mm256_min_ps(h, _mm256_blendv_ps(h, upper, upper_on));
  b.hi = _mm256_blendv_ps(_mm256_max_ps(b.hi, b.lo), b.lo, hidden);
  b.c_lo = _mm256_sqrt_ps(_mm256_max_ps(_mm256_fnmadd_ps(b.lo, b.lo, q), zero));
  b.c_hi = _mm256_sqrt_ps(_mm256_max_ps(_mm256_fnmadd_ps(b.hi, b.hi, q), zero));
  return b;
}
#endif

// Chords of a cap wholly in front of the tangent plane, in u (see the header): the horizon
// bounds u by square roots alone and the chord integral of (n.w) / c0 du is
//   nc (hi - lo) + ns s (asin(hi / sq) - asin(lo / sq)) + nu (c0(lo) - c0(hi)),
// c0(u) = sqrt(q - u^2), q = 1 - s^2, sq = sqrt(q). Eight chords at a time in registers (AVX2,
// with a scalar fallback doing the same operations).
float front_chords(const CapFrame& f) {
  const int end = padded(f.strips);
  const bool below = f.sin_e<0, above = f.sin_e> 0;
#ifdef __AVX2__
  const __m256 rho = _mm256_set1_ps(f.rho), one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 sin_e = _mm256_set1_ps(f.sin_e), cos_e = _mm256_set1_ps(f.cos_e);
  const __m256 tiny = _mm256_set1_ps(1e-30f);
  const __m256 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
  const __m256 nc = _mm256_set1_ps(f.nc), ns = _mm256_set1_ps(f.ns), nu = _mm256_set1_ps(f.nu);
  __m256 acc = zero;
  for (int j = 0; j < end; j += kLanes) {
    const __m256 sn = _mm256_loadu_ps(f.sin_psi + j);
    const __m256 s = _mm256_mul_ps(rho, _mm256_loadu_ps(f.cos_psi + j));
    const __m256 h = _mm256_mul_ps(rho, sn);
    const __m256 q = _mm256_fnmadd_ps(s, s, one);
    const ChordBounds cb = chord_bounds8(_mm256_loadu_ps(f.horizon + j), q, h, sin_e, cos_e,
                                         below ? all : zero, above ? all : zero);
    const __m256 lo = cb.lo, hi = cb.hi, c_lo = cb.c_lo, c_hi = cb.c_hi;
    // asin(v / sq) = atan(v / c0(v)).
    const __m256 as = _mm256_sub_ps(detail::fast_atan_ratio8(hi, _mm256_max_ps(c_hi, tiny)),
                                    detail::fast_atan_ratio8(lo, _mm256_max_ps(c_lo, tiny)));
    // c0(lo) - c0(hi) in product form: tiny caps keep their precision.
    const __m256 len = _mm256_sub_ps(hi, lo);
    const __m256 dc = _mm256_div_ps(_mm256_mul_ps(len, _mm256_add_ps(hi, lo)),
                                    _mm256_max_ps(_mm256_add_ps(c_lo, c_hi), tiny));
    const __m256 chord =
        _mm256_fmadd_ps(nc, len, _mm256_fmadd_ps(_mm256_mul_ps(ns, s), as, _mm256_mul_ps(nu, dc)));
    acc = _mm256_fmadd_ps(sn, chord, acc);
  }
  const __m128 s4 = _mm_add_ps(_mm256_castps256_ps128(acc), _mm256_extractf128_ps(acc, 1));
  const __m128 s2 = _mm_add_ps(s4, _mm_movehl_ps(s4, s4));
  return _mm_cvtss_f32(_mm_add_ss(s2, _mm_movehdup_ps(s2)));
#else
  float sum = 0;
  for (int j = 0; j < end; ++j) {
    const float sn = f.sin_psi[j], s = f.rho * f.cos_psi[j], h = f.rho * sn, aj = f.horizon[j];
    const float q = 1 - s * s, r = std::sqrt(q);
    const float root = std::sqrt(std::max(q - aj * aj, 0.0f));
    const float lower = aj * f.cos_e - root * f.sin_e, upper = aj * f.cos_e + root * f.sin_e;
    const float cr = f.cos_e * r;
    const bool valid = aj > -r;
    const bool lower_on = valid && (below || aj > -cr);
    const bool upper_on = valid && above && aj > cr;
    const bool hidden = aj >= r || (!above && aj >= cr);
    const float lo = std::max(-h, lower_on ? lower : -h);
    float hi = std::min(h, upper_on ? upper : h);
    hi = hidden ? lo : std::max(hi, lo);
    const float c_lo = std::sqrt(std::max(q - lo * lo, 0.0f));
    const float c_hi = std::sqrt(std::max(q - hi * hi, 0.0f));
    const float as = detail::fast_atan(hi / std::max(c_hi, 1e-30f)) -
                     detail::fast_atan(lo / std::max(c_lo, 1e-30f));
    const float dc = (hi - lo) * (hi + lo) / std::max(c_lo + c_hi, 1e-30f);
    sum += sn * (f.nc * (hi - lo) + f.ns * s * as + f.nu * dc);
  }
  return sum;
#endif
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
    const float t_max = detail::fast_asin(std::min(h / r, 1.0f));
    float lo = -t_max, hi = t_max;
    const float ratio = f.horizon[j] / r;
    if (ratio >= 1) continue;  // the whole chord is below the horizon
    if (ratio > -1) {
      const float as = detail::fast_asin(ratio);  // e + t in (as, pi - as)
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
        const float width = detail::fast_acos(b);
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
    sh[j] = detail::fast_sin(std::clamp(horizon[j], -kHalfPi, kHalfPi));
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
  const std::size_t at = strip_nodes().offsets[strips];
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
  alignas(32) std::array<float, kMaxStrips> chord_horizon;
  const float* tau = nodes().tau[count].data();
  for (int j = strips; j < padded(strips); ++j) chord_horizon[j] = -1.0f;
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

unsigned cap_transfer8(const CapLanes& in, float radius, float wide, int strips, bool defer_chords,
                       float* e) {
  strips = std::clamp(strips, 1, kMaxStrips);
  const int count = std::clamp(in.count, 1, kMaxCapHorizons);
#ifdef __AVX2__
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
  __m256 sh[kMaxCapHorizons];
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
  const __m256 need = _mm256_or_ps(front_chords, cut);
  const __m256 other = defer_chords ? _mm256_or_ps(is_wide, need) : is_wide;
  const __m256 chords = defer_chords ? zero : _mm256_and_ps(need, front_chords);
  const __m256 cut_chords = defer_chords ? zero : cut;
  __m256 value = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(kPi), _mm256_mul_ps(rho, rho)), nc);
  const __m256 any_chords = _mm256_or_ps(chords, cut_chords);
  if (!_mm256_testz_ps(any_chords, any_chords)) {
    // The cap's frame (cap_transfer): side = (-pd.y, pd.x, 0), up = (-sin_e pd, cos_e).
    const __m256 has_plane = _mm256_cmp_ps(plane, zero, _CMP_GT_OQ);
    const __m256 inv_plane = _mm256_div_ps(one, _mm256_max_ps(plane, _mm256_set1_ps(1e-30f)));
    const __m256 pdx = _mm256_blendv_ps(one, _mm256_mul_ps(dx, inv_plane), has_plane);
    const __m256 pdy = _mm256_and_ps(has_plane, _mm256_mul_ps(dy, inv_plane));
    const __m256 ns = _mm256_fmsub_ps(ny, pdx, _mm256_mul_ps(nx, pdy));
    const __m256 nu = _mm256_fmsub_ps(
        nz, cos_e, _mm256_mul_ps(sin_e, _mm256_fmadd_ps(ny, pdy, _mm256_mul_ps(nx, pdx))));
    // The horizon along each chord: linear in tau = cos(psi) between the samples, as
    // cap_transfer (the weights depend on the chord only); open: -1.
    __m256 chord_a[kMaxStrips];
    const StripNodes& sn = strip_nodes();
    const float* cos_psi = sn.cos_psi.data() + sn.offsets[strips];
    const float* tau = nodes().tau[count].data();
    const __m256 minus_one = _mm256_set1_ps(-1.0f);
    for (int j = 0; j < strips; ++j) {
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
    if (!_mm256_testz_ps(chords, chords))
      sum = front_chords8(rho, nc, ns, nu, sin_e, cos_e, chord_a, strips);
    if (!_mm256_testz_ps(cut_chords, cut_chords))
      sum = _mm256_blendv_ps(
          sum, general_chords8(rho, cos_half, nc, ns, nu, sin_e, cos_e, chord_a, strips),
          cut_chords);
    const __m256 scaled = _mm256_max_ps(
        _mm256_mul_ps(sum, _mm256_mul_ps(rho, _mm256_set1_ps(kPi / static_cast<float>(strips)))),
        zero);
    value = _mm256_blendv_ps(value, scaled, any_chords);
  }
  _mm256_storeu_ps(e, _mm256_and_ps(_mm256_andnot_ps(other, visible), value));
  return static_cast<unsigned>(_mm256_movemask_ps(other));
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

}  // namespace penumbra::terrain_shadow
