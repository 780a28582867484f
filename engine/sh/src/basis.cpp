#include "penumbra/sh/basis.h"

#include <cstring>
#include <numbers>

#include "../generated/basis_generated.h"
#include "penumbra/sh/lanes.h"

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
constexpr std::size_t kLanes = kLaneCount;

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
    for (int i = 0; i < N * N; ++i)
      std::memcpy(out + static_cast<std::size_t>(i) * count + d, &rows[i], sizeof(Lanes));
  }
  for (; d < count; ++d) {  // tail
    float tmp[N * N];
    eval_xyz<N>(x[d], y[d], z[d], tmp);
    for (int i = 0; i < N * N; ++i) out[static_cast<std::size_t>(i) * count + d] = tmp[i];
  }
}

template <int N>
void eval_basis_lanes(const Lanes& x, const Lanes& y, const Lanes& z, Lanes* out) {
  eval_lanes<N>(x, y, z, out);
}

template <int N>
void add_cap_lanes(const Lanes& x, const Lanes& y, const Lanes& z, const Lanes& cos_angle,
                   const Lanes& scale, Lanes* acc, Lanes* basis_out) {
  Lanes p[N + 1];  // Legendre P_0..P_N at the caps' cosines
  p[0] = splat(1.0f);
  p[1] = cos_angle;
  for (int l = 1; l < N; ++l)  // (l + 1) P_{l+1} = (2l + 1) x P_l - l P_{l-1}, by reciprocals
    p[l + 1] = (static_cast<float>(2 * l + 1) / static_cast<float>(l + 1)) * cos_angle * p[l] -
               (static_cast<float>(l) / static_cast<float>(l + 1)) * p[l - 1];
  Lanes basis[N * N];
  eval_lanes<N>(x, y, z, basis);
  const Lanes s = scale * (2 * std::numbers::pi_v<float>);
  for (int l = 0; l < N; ++l) {
    const Lanes below = l == 0 ? splat(1.0f) : p[l - 1];
    const Lanes k = s * (below - p[l + 1]) * (1.0f / static_cast<float>(2 * l + 1));
    for (int m = -l; m <= l; ++m) acc[index(l, m)] += k * basis[index(l, m)];
  }
  if (basis_out)
    for (int i = 0; i < N * N; ++i) basis_out[i] = basis[i];
}

template <int N>
float evaluate(const Coeffs<N>& f, const glm::vec3& dir) {
  float y[N * N];
  eval_xyz<N>(dir.x, dir.y, dir.z, y);
  float s = 0;
  for (int i = 0; i < N * N; ++i) s += f[i] * y[i];
  return s;
}

#define PENUMBRA_SH_INSTANTIATE(N)                                                         \
  template void eval_basis<N>(const glm::vec3&, float*);                                   \
  template void eval_basis_batch<N>(const float*, const float*, const float*, std::size_t, \
                                    float*);                                               \
  template float evaluate<N>(const Coeffs<N>&, const glm::vec3&);                          \
  template void eval_basis_lanes<N>(const Lanes&, const Lanes&, const Lanes&, Lanes*);     \
  template void add_cap_lanes<N>(const Lanes&, const Lanes&, const Lanes&, const Lanes&,   \
                                 const Lanes&, Lanes*, Lanes*);
PENUMBRA_SH_INSTANTIATE(2)
PENUMBRA_SH_INSTANTIATE(3)
PENUMBRA_SH_INSTANTIATE(4)
PENUMBRA_SH_INSTANTIATE(5)
PENUMBRA_SH_INSTANTIATE(6)
#undef PENUMBRA_SH_INSTANTIATE

}  // namespace penumbra::sh
