// Eight floats in one AVX2 register (a GCC/Clang vector type) and the few operations on it that
// the batched SH code needs: per-lane select, sqrt, min/max, loads and stores. Shared by the SH
// batch code (batch.h) and callers that build their own eight-lane loops over SH (the blocker
// accumulation's pairs). Also the SH operations on lanes: the basis at eight directions, and a
// cap's indicator added for eight caps at once.
// Threading: pure functions.
#pragma once

#include <cstring>

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace penumbra::sh {

using Lanes = float __attribute__((vector_size(32)));
using LaneMask = int __attribute__((vector_size(32)));
inline constexpr int kLaneCount = 8;
static_assert(sizeof(Lanes) == kLaneCount * sizeof(float));

inline Lanes splat(float x) {
  return Lanes{} + x;
}
inline Lanes load_lanes(const float* p) {  // kLaneCount floats, any alignment
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store_lanes(const Lanes& v, float* p) {
  std::memcpy(p, &v, sizeof v);
}
// m ? a : b per lane (m all ones or zero, as a comparison gives).
inline Lanes select(LaneMask m, Lanes a, Lanes b) {
  LaneMask ai, bi;
  std::memcpy(&ai, &a, sizeof a);
  std::memcpy(&bi, &b, sizeof b);
  const LaneMask r = (ai & m) | (bi & ~m);
  Lanes out;
  std::memcpy(&out, &r, sizeof out);
  return out;
}
inline Lanes lane_min(Lanes a, Lanes b) {
  return select(a < b, a, b);
}
inline Lanes lane_max(Lanes a, Lanes b) {
  return select(a > b, a, b);
}
inline Lanes lane_clamp01(Lanes x) {
  return lane_min(lane_max(x, Lanes{}), splat(1.0f));
}
// sqrt per lane; lanes below 0 (and NaN) give 0.
inline Lanes lane_sqrt(Lanes x) {
  x = select(x > 0.0f, x, Lanes{});
#if defined(__AVX__)
  return (Lanes)_mm256_sqrt_ps((__m256)x);
#else
  float f[kLaneCount];
  store_lanes(x, f);
  for (float& v : f) v = __builtin_sqrtf(v);
  return load_lanes(f);
#endif
}
// Bit l set where lane l of the mask is set.
inline unsigned lane_bits(LaneMask m) {
#if defined(__AVX__)
  return static_cast<unsigned>(_mm256_movemask_ps((__m256)m));
#else
  unsigned bits = 0;
  for (int l = 0; l < kLaneCount; ++l) bits |= (m[l] != 0 ? 1u : 0u) << l;
  return bits;
#endif
}

// Horizontal sum of the lanes.
inline float lane_sum(Lanes x) {
  float f[kLaneCount];
  store_lanes(x, f);
  return ((f[0] + f[1]) + (f[2] + f[3])) + ((f[4] + f[5]) + (f[6] + f[7]));
}

// out[i] = y_i at the eight unit directions (x, y, z), i < N*N (basis.h, same polynomials).
template <int N>
void eval_basis_lanes(const Lanes& x, const Lanes& y, const Lanes& z, Lanes* out);

// acc[i] += scale * cap_i for eight caps: cap_i the SH of the indicator of the cap about the
// unit axis (x, y, z) whose half-angle has cosine `cos_angle` (zh.h zh_cap, rotated):
// coefficient (l, m) gains scale 2 pi / (2l + 1) (P_{l-1}(c) - P_{l+1}(c)) y_lm(axis), P_{-1} = 1
// ([Giraud] eq. 26 with scale = weight log eps). Lanes with scale 0 add nothing. `basis`, when
// given, receives y_i at the axes (N*N lanes), as eval_basis_lanes.
template <int N>
void add_cap_lanes(const Lanes& x, const Lanes& y, const Lanes& z, const Lanes& cos_angle,
                   const Lanes& scale, Lanes* acc, Lanes* basis = nullptr);

}  // namespace penumbra::sh
