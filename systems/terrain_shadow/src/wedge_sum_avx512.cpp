// WedgeTable::visibility's wedge loop (wedge_table.cpp) for AVX-512: two of a node's 8-float
// blocks in one 512-bit vector, the same multiply-adds per float in the same order (so the same
// floats). Chosen at run time by visibility() (sweep_isa()).
#include "wedge_sum.h"

#ifdef __AVX2__
#include "avx512_target_begin.h"  // to avx512_target_end.h below

#include <immintrin.h>

namespace penumbra::terrain_shadow::detail::avx512 {
namespace {

// [Meier13] eq. 4.19: u += A_k w_k, t += B'_k w_k, w_k the bilinear wedge (wedge_table.cpp).
// Per float in the 8-lane loop's order (as GCC contracts it): w = g01 c00[kB + v], then
// multiply-adds of g00 c00[v], g10 c10[v] and g11 c10[kB + v]. Blocks 2 p and 2 p + 1 share a
// vector; an odd last block takes the lower half (masked loads and stores: the upper lanes
// read nothing and are not stored).
template <int kB>
void sum(const WedgeSumInput& in, float* u, float* t) {
  constexpr int kVectors = (kB + 1) / 2;
  auto mask = [](int p) -> __mmask16 { return 2 * p + 1 < kB ? 0xffff : 0x00ff; };
  __m512 u16[kVectors], t16[kVectors];
  for (int p = 0; p < kVectors; ++p) {
    u16[p] = _mm512_maskz_loadu_ps(mask(p), u + 16 * p);
    t16[p] = _mm512_maskz_loadu_ps(mask(p), t + 16 * p);
  }
  const float* rot = in.rotation;
  for (int j = 0; j < in.count; ++j, rot += 2 * kB * 8) {
    const float* c00 = in.table + (static_cast<std::size_t>(in.index[j]) * in.row +
                                   static_cast<std::size_t>(in.index[j + 1]) * kB) *
                                      8;
    const float* c10 = c00 + in.row * 8;
    const __m512 g00 = _mm512_set1_ps(in.g00[j]), g01 = _mm512_set1_ps(in.g01[j]);
    const __m512 g10 = _mm512_set1_ps(in.g10[j]), g11 = _mm512_set1_ps(in.g11[j]);
    for (int p = 0; p < kVectors; ++p) {
      const int o = 16 * p;
      const __mmask16 m = mask(p);
      __m512 w = _mm512_mul_ps(g01, _mm512_maskz_loadu_ps(m, c00 + kB * 8 + o));
      w = _mm512_fmadd_ps(g00, _mm512_maskz_loadu_ps(m, c00 + o), w);
      w = _mm512_fmadd_ps(g10, _mm512_maskz_loadu_ps(m, c10 + o), w);
      w = _mm512_fmadd_ps(g11, _mm512_maskz_loadu_ps(m, c10 + kB * 8 + o), w);
      u16[p] = _mm512_fmadd_ps(_mm512_maskz_loadu_ps(m, rot + o), w, u16[p]);
      t16[p] = _mm512_fmadd_ps(_mm512_maskz_loadu_ps(m, rot + kB * 8 + o), w, t16[p]);
    }
  }
  for (int p = 0; p < kVectors; ++p) {
    _mm512_mask_storeu_ps(u + 16 * p, mask(p), u16[p]);
    _mm512_mask_storeu_ps(t + 16 * p, mask(p), t16[p]);
  }
}

}  // namespace

void wedge_sum(const WedgeSumInput& in, float* u, float* t) {
  switch (in.blocks) {
    case 1:
      return sum<1>(in, u, t);
    case 2:
      return sum<2>(in, u, t);
    case 3:
      return sum<3>(in, u, t);
    case 4:
      return sum<4>(in, u, t);
    case 5:
      return sum<5>(in, u, t);
    case 6:
      return sum<6>(in, u, t);
    case 7:
      return sum<7>(in, u, t);
    default:
      return;  // wedge_sum.h: blocks in [1, kMaxWedgeBlocks]
  }
}

}  // namespace penumbra::terrain_shadow::detail::avx512

#include "avx512_target_end.h"
#endif
