#include "penumbra/systems/terrain_shadow/cap_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "cap_chords.h"
#include "fast_math.h"

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace penumbra::terrain_shadow {
namespace {

using detail::CapFrame;
using detail::fast_atan_ratio;
using detail::fast_cos;
using detail::fast_sin;
using detail::kHalfPi;
using detail::kLanes;
using detail::kMaxStrips;
using detail::kPi;
using detail::nodes;
using detail::padded;
using detail::strip_nodes;

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

namespace detail {

float front_lens(const LightCap& cap, const glm::vec3& n, float omega) {
  // front_lens8's operations, one lane.
  const float rho = cap.rho, rho2 = rho * rho;
  const float omc = rho2 / (1 + cap.cos_half);  // 1 - cos(beta), accurately
  const float cos_o = fast_cos(omega);
  const float d_sin = fast_sin(omega) - cap.sin_e, d_cos = cap.cos_e - cos_o;
  const float nw = n.x * cap.plane_dir.x + n.y * cap.plane_dir.y;
  const float nu = n.z * cap.cos_e - cap.sin_e * nw;
  const float nc = glm::dot(n, cap.dir);
  const float cphi =
      std::clamp((cap.sin_e * omc + d_sin) / std::max(rho * cap.cos_e, 1e-30f), -1.0f, 1.0f);
  const float sphi = std::sqrt(std::max((1 - cphi) * (1 + cphi), 0.0f));
  const float phi = kHalfPi - fast_atan_ratio(cphi, sphi);
  const float chord2 = d_sin * d_sin + d_cos * d_cos;  // cos(omega - e) = 1 - chord2 / 2
  const float k = std::clamp((omc - 0.5f * chord2) / std::max(cos_o * cap.cos_e, 1e-30f), 0.0f,
                             2.0f);  // 1 - cos(psi)
  const float hk = 0.5f * k;
  const float psi = 2 * fast_atan_ratio(std::sqrt(hk), std::sqrt(1 - hk));
  const float spsi = std::sqrt(k * (2 - k));
  const float ends = omc * nu - d_sin * nw - d_cos * n.z;
  const float arcs = (psi - spsi) * (cos_o * cos_o) * n.z + phi * rho2 * nc;
  return std::max(rho * sphi * ends + arcs, 0.0f);
}

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

}  // namespace detail

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

  if (count == 1 && nc >= rho)  // a constant horizon: the lens in closed form
    return detail::front_lens(cap, n, std::clamp(horizon[0], -kHalfPi, kHalfPi));

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
  const float sum = nc >= rho ? detail::front_chords(f) : detail::general_chords(f);
  return std::max(sum * rho * kPi / static_cast<float>(strips), 0.0f);
}

}  // namespace penumbra::terrain_shadow
