// Internal: what cap_transfer (one receiver, cap_transfer.cpp) and cap_transfer8 (eight,
// cap_transfer_lanes.cpp) share: the horizon samples' and the strips' nodes, a receiver's cap in
// the chords' frame, the chord bounds on eight lanes, and the one-receiver chord integrals
// (cap_transfer.h has the method).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "lanes.h"
#include "penumbra/systems/terrain_shadow/cap_transfer.h"

namespace penumbra::terrain_shadow::detail {

// tau_j of cap_horizon_direction for count 1..kMaxCapHorizons, ascending.
struct HorizonNodes {
  std::array<std::array<float, kMaxCapHorizons>, kMaxCapHorizons + 1> tau{};
  HorizonNodes() {
    for (int count = 1; count <= kMaxCapHorizons; ++count)
      for (int j = 0; j < count; ++j)
        tau[count][j] = static_cast<float>(-std::cos(std::numbers::pi * (j + 1) / (count + 1)));
  }
};
inline const HorizonNodes& nodes() {
  static const HorizonNodes n;  // initialised on first use, thread-safe
  return n;
}

// Chord nodes of cap_transfer for 1..kMaxStrips strips: cos and sin of psi_j, each count's
// block padded with zeros to a multiple of kLanes (a padding chord has zero length and weight).
constexpr int kMaxStrips = kMaxCapStrips;
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
inline const StripNodes& strip_nodes() {
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

// A cap wholly in front of the tangent plane above a constant horizon (elevation omega,
// radians, in [-pi/2, pi/2]), in closed form: the part of the cap above the horizon is a lens
// bounded by an arc of the cap's circle (axis c, angular radius b, sin b = rho) and an arc of
// the horizon's (axis z, radius pi/2 - omega), and int n.w dw = n . (1/2) oint w x dw along
// the two arcs [Arvo95] (Stokes). An arc of half-angle phi of a circle (axis a, radius b)
// centred on the unit in-plane direction p gives (1/2) int w x dw = phi sin^2 b a - sin(phi)
// sin b cos b p. With h the centre's horizontal direction, u_c = cos e z - sin e h (up at the
// centre) and t_h = cos(omega) z - sin(omega) h (up at the horizon), the two arcs' first-order
// parts share the chord's half-length l = rho sin(phi) = cos(omega) sin(psi), so they are
// written as l times a difference of nearby unit vectors (no cancellation for small caps):
//   phi rho^2 nc + (psi - sin psi) cos^2(omega) nz + l (n.(t_h - u_c) + (1 - cos b) n.u_c),
// with t_h - u_c = (cos(omega) - cos e) z - (sin(omega) - sin e) h, and cos(phi), cos(psi)
// from where the circles meet (clamped: one circle wholly inside or outside the other).
float front_lens(const LightCap& cap, const glm::vec3& n, float omega);

// The chord integrals of one receiver's cap (cap_transfer.cpp): caps wholly in front of the
// tangent plane, and any cap.
float front_chords(const CapFrame& f);
float general_chords(const CapFrame& f);

}  // namespace penumbra::terrain_shadow::detail
