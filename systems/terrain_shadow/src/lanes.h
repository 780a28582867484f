// Internal: eight floats on vector lanes (GCC/Clang vector extension, as in sh/basis.cpp), with
// unaligned loads and stores; shared by the wedge-table and log-wedge inner loops.
#pragma once

#include <cstring>

namespace penumbra::terrain_shadow::detail {

using Lanes = float __attribute__((vector_size(32)));

inline Lanes load(const float* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline void store(float* p, Lanes v) {
  std::memcpy(p, &v, sizeof v);
}

}  // namespace penumbra::terrain_shadow::detail
