// Internal: eight floats on vector lanes (GCC/Clang vector extension, as in sh/basis.cpp), with
// unaligned loads and stores; shared by the wedge-table and log-wedge inner loops. And an 8 x 8
// transpose in AVX2 registers (the sweep's planes, the transfer's eight-texel couplings).
#pragma once

#include <cstring>

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace penumbra::terrain_shadow::detail {

using Lanes = float __attribute__((vector_size(32)));
inline constexpr int kLanes = 8;  // floats in a Lanes

inline Lanes load(const float* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline void store(float* p, Lanes v) {
  std::memcpy(p, &v, sizeof v);
}

#ifdef __AVX2__
// m[i][j] <- m[j][i]. Always inlined (fast_math.h says why).
[[gnu::always_inline]] inline void transpose8(__m256 m[8]) {
  __m256 t[8], s[8];
  for (int i = 0; i < 8; i += 2) {
    t[i] = _mm256_unpacklo_ps(m[i], m[i + 1]);
    t[i + 1] = _mm256_unpackhi_ps(m[i], m[i + 1]);
  }
  for (int i = 0; i < 8; i += 4) {
    s[i] = _mm256_shuffle_ps(t[i], t[i + 2], _MM_SHUFFLE(1, 0, 1, 0));
    s[i + 1] = _mm256_shuffle_ps(t[i], t[i + 2], _MM_SHUFFLE(3, 2, 3, 2));
    s[i + 2] = _mm256_shuffle_ps(t[i + 1], t[i + 3], _MM_SHUFFLE(1, 0, 1, 0));
    s[i + 3] = _mm256_shuffle_ps(t[i + 1], t[i + 3], _MM_SHUFFLE(3, 2, 3, 2));
  }
  for (int i = 0; i < 4; ++i) {
    m[i] = _mm256_permute2f128_ps(s[i], s[i + 4], 0x20);
    m[i + 4] = _mm256_permute2f128_ps(s[i], s[i + 4], 0x31);
  }
}
#endif

}  // namespace penumbra::terrain_shadow::detail
