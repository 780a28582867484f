#include "penumbra/sh/basis.h"

#include <cstring>

#include "../generated/basis_generated.h"

namespace penumbra::sh {
namespace {
template <int N>
inline void eval_xyz(float x, float y, float z, float* out) {
  static_assert(N >= 2 && N <= kMaxBands, "2 to 6 bands");
  if constexpr (N == 2) generated::eval_basis_2(x, y, z, out);
  if constexpr (N == 3) generated::eval_basis_3(x, y, z, out);
  if constexpr (N == 4) generated::eval_basis_4(x, y, z, out);
  if constexpr (N == 5) generated::eval_basis_5(x, y, z, out);
  if constexpr (N == 6) generated::eval_basis_6(x, y, z, out);
}
}  // namespace

template <int N>
void eval_basis(const glm::vec3& dir, float* out) {
  eval_xyz<N>(dir.x, dir.y, dir.z, out);
}

// Eight directions per step: the generated polynomials run on a GCC/Clang float vector, and
// each coefficient row is written with one contiguous 32-byte store.
using Lanes = float __attribute__((vector_size(32)));
constexpr std::size_t kLanes = 8;

template <int N>
inline void eval_lanes(Lanes x, Lanes y, Lanes z, Lanes* out) {
  if constexpr (N == 2) generated::eval_basis_2(x, y, z, out);
  if constexpr (N == 3) generated::eval_basis_3(x, y, z, out);
  if constexpr (N == 4) generated::eval_basis_4(x, y, z, out);
  if constexpr (N == 5) generated::eval_basis_5(x, y, z, out);
  if constexpr (N == 6) generated::eval_basis_6(x, y, z, out);
}

template <int N>
void eval_basis_batch(const float* x, const float* y, const float* z, std::size_t count,
                      float* out) {
  std::size_t d = 0;
  for (; d + kLanes <= count; d += kLanes) {
    Lanes vx, vy, vz, rows[N * N];
    std::memcpy(&vx, x + d, sizeof vx);
    std::memcpy(&vy, y + d, sizeof vy);
    std::memcpy(&vz, z + d, sizeof vz);
    eval_lanes<N>(vx, vy, vz, rows);
    for (int i = 0; i < N * N; ++i) std::memcpy(out + static_cast<std::size_t>(i) * count + d, &rows[i], sizeof(Lanes));
  }
  for (; d < count; ++d) {  // tail
    float tmp[N * N];
    eval_xyz<N>(x[d], y[d], z[d], tmp);
    for (int i = 0; i < N * N; ++i) out[static_cast<std::size_t>(i) * count + d] = tmp[i];
  }
}

template <int N>
float evaluate(const Coeffs<N>& f, const glm::vec3& dir) {
  float y[N * N];
  eval_xyz<N>(dir.x, dir.y, dir.z, y);
  float s = 0;
  for (int i = 0; i < N * N; ++i) s += f[i] * y[i];
  return s;
}

#define PENUMBRA_SH_INSTANTIATE(N)                                                       \
  template void eval_basis<N>(const glm::vec3&, float*);                                \
  template void eval_basis_batch<N>(const float*, const float*, const float*, std::size_t, \
                                    float*);                                            \
  template float evaluate<N>(const Coeffs<N>&, const glm::vec3&);
PENUMBRA_SH_INSTANTIATE(2)
PENUMBRA_SH_INSTANTIATE(3)
PENUMBRA_SH_INSTANTIATE(4)
PENUMBRA_SH_INSTANTIATE(5)
PENUMBRA_SH_INSTANTIATE(6)
#undef PENUMBRA_SH_INSTANTIATE

}  // namespace penumbra::sh
