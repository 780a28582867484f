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
