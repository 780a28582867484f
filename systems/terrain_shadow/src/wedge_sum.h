// Internal: WedgeTable::visibility's loop over a chunk of azimuths (wedge_table.cpp), compiled
// for AVX-512 by wedge_sum_avx512.cpp and chosen at run time (sweep_lanes.h's sweep_isa()).
#pragma once

#include <cstddef>

namespace penumbra::terrain_shadow::detail {

inline constexpr int kMaxWedgeBlocks = 7;  // 8-float blocks of a node: ceil(N^2 / 8), N <= 7

// One chunk: azimuth j's bilinear lookup is at nodes (index[j], index[j + 1]) with weights
// g00[j] .. g11[j]; `table` is the WedgeTable's nodes (8-float blocks, `row` blocks a row, a
// node `blocks` blocks) and `rotation` the chunk's first azimuth's 2 `blocks` blocks.
struct WedgeSumInput {
  const float* table;
  std::size_t row;
  int blocks;
  const float* rotation;
  const int* index;
  const float *g00, *g01, *g10, *g11;
  int count;
};

namespace avx512 {
// u[i] += A_k,i w_k,i and t[i] += B'_k,i w_k,i over the chunk's azimuths k, i < 8 blocks:
// the 8-lane loop's floats.
void wedge_sum(const WedgeSumInput& in, float* u, float* t);
}  // namespace avx512

}  // namespace penumbra::terrain_shadow::detail
