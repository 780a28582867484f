// Diffuse transfer and spherical-light radiance ([Meier13] eq. 4.20-4.21,
// 4.27-4.29, appendix A.1). Pure functions, safe to call from any thread.
#include "penumbra/systems/terrain_shadow/transfer.h"

#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include <glm/geometric.hpp>

#include "penumbra/sh/product.h"
#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"

#include "fast_math.h"
#include "lanes.h"
#include "sh_any.h"

namespace penumbra::terrain_shadow {

template <int N>
sh::Coeffs<N> diffuse_transfer(const sh::Coeffs<N>& visibility, const glm::vec3& normal) {
  assert(std::abs(glm::dot(normal, normal) - 1) < 1e-3f && "diffuse_transfer: normal not unit");
  // zh_clamped_cosine is the projection of max(cos, 0) itself (DC pi / sqrt(4 pi)), so
  // L . transfer is the irradiance integral L V max(n.w, 0) dw, without a 1 / pi (eq. 4.21).
  static const sh::Zonal<N> kCosine = sh::zh_clamped_cosine<N>();
  return sh::product<N>(visibility, sh::rotate_zh<N>(kCosine, normal));
}

namespace {

// G_ij = integral y_i y_j (x, y, z) dw for i < N^2, j < (N + 1)^2, by a quadrature exact for the
// degree-2N integrand; one sparse list per component (non-zero only for |l_i - l_j| = 1), each
// in slot order (the k-th entry of every output, then the (k+1)-th) so that consecutive
// multiply-adds go to different outputs.
struct Coupling {
  std::uint16_t i, j;
  float g;
};
template <int N>
struct Couplings {
  std::vector<Coupling> c[3];  // x, y, z
};
template <int N>
Couplings<N> couplings() {
  constexpr int M = N + 1;
  const sh::SphereQuadrature q = sh::SphereQuadrature::gauss(M + 1, 2 * M + 2);
  std::vector<double> g(static_cast<std::size_t>(3 * N * N * M * M), 0.0);
  std::vector<double> y(M * M);
  for (std::size_t d = 0; d < q.directions.size(); ++d) {
    const glm::dvec3 w = glm::normalize(glm::dvec3(q.directions[d]));
    detail::eval_basis_any(M, w.x, w.y, w.z, y.data());
    for (int i = 0; i < N * N; ++i)
      for (int j = 0; j < M * M; ++j)
        for (int c = 0; c < 3; ++c)
          g[(static_cast<std::size_t>(i) * M * M + j) * 3 + c] += q.weights[d] * y[i] * y[j] * w[c];
  }
  Couplings<N> out;
  for (int c = 0; c < 3; ++c) {
    std::vector<std::vector<Coupling>> slots;
    for (int i = 0; i < N * N; ++i) {
      std::size_t k = 0;
      for (int j = 0; j < M * M; ++j) {
        const double gij = g[(static_cast<std::size_t>(i) * M * M + j) * 3 + c];
        if (std::abs(gij) < 1e-6) continue;
        if (slots.size() <= k) slots.emplace_back();
        slots[k++].push_back({static_cast<std::uint16_t>(i), static_cast<std::uint16_t>(j),
                              static_cast<float>(gij)});
      }
    }
    for (const auto& slot : slots) out.c[c].insert(out.c[c].end(), slot.begin(), slot.end());
  }
  return out;
}

}  // namespace

template <int N>
sh::Coeffs<N> exact_diffuse_transfer(const sh::Coeffs<N + 1>& visibility, const glm::vec3& normal) {
  assert(std::abs(glm::dot(normal, normal) - 1) < 1e-3f &&
         "exact_diffuse_transfer: normal not unit");
  // [Meier13] eq. 4.20's integrand projected exactly (ours), not eq. 4.21's truncated product:
  // out = n_x (G_x V) + n_y (G_y V) + n_z (G_z V).
  static const Couplings<N> kG = couplings<N>();
  sh::Coeffs<N> part[3] = {};
  for (int c = 0; c < 3; ++c)
    for (const Coupling& e : kG.c[c]) part[c][e.i] += e.g * visibility[e.j];
  sh::Coeffs<N> out;
  for (int i = 0; i < N * N; ++i)
    out[i] = normal.x * part[0][i] + normal.y * part[1][i] + normal.z * part[2][i];
  return out;
}

template <int N>
void exact_diffuse_transfer_8(const sh::Coeffs<N + 1>* visibility, const glm::vec3* normals,
                              sh::Coeffs<N>* out) {
  // exact_diffuse_transfer on eight texels at once, one per vector lane: the same multiply-adds
  // in the same order per texel, each coupling one vector operation instead of eight.
  using detail::Lanes;
  constexpr int M = N + 1;
  static const Couplings<N> kG = couplings<N>();
  Lanes v[M * M];
  int j0 = 0;  // coefficients below j0 are in v already
#ifdef __AVX2__
  for (; j0 + 8 <= M * M; j0 += 8) {  // 8 x 8 blocks transposed in registers
    __m256 m[8];
    for (int l = 0; l < 8; ++l) m[l] = _mm256_loadu_ps(visibility[l].data() + j0);
    detail::transpose8(m);
    for (int k = 0; k < 8; ++k) std::memcpy(&v[j0 + k], &m[k], sizeof(Lanes));
  }
#endif
  for (int j = j0; j < M * M; ++j)
    for (int l = 0; l < 8; ++l) v[j][l] = visibility[l][j];
  Lanes part[3][N * N] = {};
  for (int c = 0; c < 3; ++c)
    for (const Coupling& e : kG.c[c]) part[c][e.i] += e.g * v[e.j];
  Lanes nx, ny, nz;
  for (int l = 0; l < 8; ++l) nx[l] = normals[l].x, ny[l] = normals[l].y, nz[l] = normals[l].z;
  Lanes o[N * N];
  for (int i = 0; i < N * N; ++i) o[i] = nx * part[0][i] + ny * part[1][i] + nz * part[2][i];
  int i0 = 0;
#ifdef __AVX2__
  for (; i0 + 8 <= N * N; i0 += 8) {
    __m256 m[8];
    for (int k = 0; k < 8; ++k) std::memcpy(&m[k], &o[i0 + k], sizeof(Lanes));
    detail::transpose8(m);
    for (int l = 0; l < 8; ++l) _mm256_storeu_ps(out[l].data() + i0, m[l]);
  }
#endif
  for (int i = i0; i < N * N; ++i)
    for (int l = 0; l < 8; ++l) out[l][i] = o[i][l];
}

template <int N>
int exact_transfer_term_count() {
  const Couplings<N> g = couplings<N>();
  return static_cast<int>(g.c[0].size() + g.c[1].size() + g.c[2].size());
}

AzimuthFrame::AzimuthFrame(int azimuths) {
  for (int k = 0; k < azimuths; ++k) {
    const double phi = 2 * std::numbers::pi * k / azimuths;
    cos_.push_back(static_cast<float>(std::cos(phi)));
    sin_.push_back(static_cast<float>(std::sin(phi)));
  }
}

void AzimuthFrame::raise_to_tangent_plane(const float* angles, const glm::vec3& normal,
                                          float* out) const {
  // n.w = 0 along phi at tan(e) = -(n_x cos phi + n_y sin phi) / n_z (n_z > 0 on a height field).
  const int n = azimuths();
  const float inv_z = 1 / std::max(normal.z, 1e-6f);
  constexpr int kChunk = 64;
  float t[kChunk];
  for (int k0 = 0; k0 < n; k0 += kChunk) {
    const int count = std::min(kChunk, n - k0);
    for (int k = 0; k < count; ++k)
      t[k] = -(normal.x * cos_[k0 + k] + normal.y * sin_[k0 + k]) * inv_z;
    detail::fast_atan_array(t, static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k) out[k0 + k] = std::max(angles[k0 + k], t[k]);
  }
}

template <int N>
sh::Coeffs<N> spherical_light_radiance(const glm::vec3& to_centre, float radius) {
  const float d = glm::length(to_centre);
  if (!(radius > 0) || !(d > radius) || !std::isfinite(d)) return sh::Coeffs<N>{};
  // Eq. 4.27: cap of half-angle asin(r / d) about +z, rotated towards the centre.
  return sh::rotate_zh<N>(sh::zh_cap<N>(std::asin(radius / d)), to_centre / d);
}

#define PENUMBRA_TRANSFER_INSTANTIATE(N)                                                        \
  template sh::Coeffs<N> diffuse_transfer<N>(const sh::Coeffs<N>&, const glm::vec3&);           \
  template sh::Coeffs<N> spherical_light_radiance<N>(const glm::vec3&, float);                  \
  template sh::Coeffs<N> exact_diffuse_transfer<N>(const sh::Coeffs<N + 1>&, const glm::vec3&); \
  template int exact_transfer_term_count<N>();                                                  \
  template void exact_diffuse_transfer_8<N>(const sh::Coeffs<N + 1>*, const glm::vec3*,         \
                                            sh::Coeffs<N>*);
PENUMBRA_TRANSFER_INSTANTIATE(2)
PENUMBRA_TRANSFER_INSTANTIATE(3)
PENUMBRA_TRANSFER_INSTANTIATE(4)
PENUMBRA_TRANSFER_INSTANTIATE(5)
PENUMBRA_TRANSFER_INSTANTIATE(6)
#undef PENUMBRA_TRANSFER_INSTANTIATE

}  // namespace penumbra::terrain_shadow
