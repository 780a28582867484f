#include "penumbra/sh/batch.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>

#include "../generated/basis_generated.h"
#include "../generated/product_generated.h"
#include "band0.h"
#include "penumbra/sh/lanes.h"

namespace penumbra::sh {
namespace {
namespace g = generated;

static_assert(kLaneCount == kBatch);
using Mask = LaneMask;

using detail::kY0;

inline Mask finite(Lanes x) {  // std::isfinite per lane: |x| <= FLT_MAX (false for NaN)
  Mask xi;
  std::memcpy(&xi, &x, sizeof x);
  return (xi & 0x7fffffff) < 0x7f800000;
}

template <int N>
void load(const CoeffsBatch<N>& b, Lanes* f) {
  for (int i = 0; i < N * N; ++i) std::memcpy(&f[i], b.c[i], sizeof(Lanes));
}
template <int N>
void store(const Lanes* f, CoeffsBatch<N>& b) {
  for (int i = 0; i < N * N; ++i) std::memcpy(b.c[i], &f[i], sizeof(Lanes));
}

template <int N>
inline void square_lanes(const Lanes* f, Lanes* out) {
  if constexpr (N == 2) g::square_2(f, out);
  if constexpr (N == 3) g::square_3(f, out);
  if constexpr (N == 4) g::square_4(f, out);
  if constexpr (N == 5) g::square_5(f, out);
  if constexpr (N == 6) g::square_6(f, out);
}
template <int N>
inline void product_lanes(const Lanes* f, const Lanes* h, Lanes* out) {
  if constexpr (N == 2) g::product_2(f, h, out);
  if constexpr (N == 3) g::product_3(f, h, out);
  if constexpr (N == 4) g::product_4(f, h, out);
  if constexpr (N == 5) g::product_5(f, h, out);
  if constexpr (N == 6) g::product_6(f, h, out);
}
template <int N>
inline void basis_lanes(Lanes x, Lanes y, Lanes z, Lanes* out) {
  if constexpr (N == 2) g::eval_basis_2(x, y, z, out);
  if constexpr (N == 3) g::eval_basis_3(x, y, z, out);
  if constexpr (N == 4) g::eval_basis_4(x, y, z, out);
  if constexpr (N == 5) g::eval_basis_5(x, y, z, out);
  if constexpr (N == 6) g::eval_basis_6(x, y, z, out);
}

// exp_hyb (exp_log.cpp) on kBatch lanes, step for step.
template <int N>
void exp_hyb_lanes(const Lanes* f, Lanes* out, float ol_norm) {
  constexpr int kC = N * N;
  Lanes norm2{};
  for (int i = 1; i < kC; ++i) norm2 += f[i] * f[i];
  // Per lane, the scalar code's own number of squarings (ceil(log2) is not the exponent field:
  // log2f rounds), the scale 2^-k (exact), the OL fit and e^DC.
  alignas(32) float n2[kBatch], down[kBatch], dc[kBatch];
  alignas(32) int k[kBatch];
  std::memcpy(n2, &norm2, sizeof n2);
  int k_max = 0;
  for (int l = 0; l < kBatch; ++l) {
    const float norm = std::sqrt(n2[l]);
    k[l] = 0;
    if (norm > ol_norm && std::isfinite(norm))
      k[l] = static_cast<int>(std::ceil(std::log2(norm / ol_norm)));
    down[l] = std::ldexp(1.0f, -k[l]);
    k_max = std::max(k_max, k[l]);
  }
  Lanes d, scaled[kC];
  std::memcpy(&d, down, sizeof d);
  scaled[0] = Lanes{};  // DC isolation: applied exactly at the end
  for (int i = 1; i < kC; ++i) scaled[i] = f[i] * d;
  // exp_ol of the scaled part (its DC is 0, so e^{DC} = 1 there).
  Lanes ol2{};
  for (int i = 1; i < kC; ++i) ol2 += scaled[i] * scaled[i];
  alignas(32) float o2[kBatch], a[kBatch], b[kBatch];
  std::memcpy(o2, &ol2, sizeof o2);
  float f0[kBatch];
  std::memcpy(f0, &f[0], sizeof f0);
  for (int l = 0; l < kBatch; ++l) {
    const OlFit fit = ol_fit<N>(std::sqrt(o2[l]));
    a[l] = fit.a;
    b[l] = fit.b;
    dc[l] = std::exp(f0[l] * kY0);
  }
  Lanes va, vb;
  std::memcpy(&va, a, sizeof va);
  std::memcpy(&vb, b, sizeof vb);
  Lanes gl[kC];
  gl[0] = va / kY0;
  for (int i = 1; i < kC; ++i) gl[i] = vb * scaled[i];
  // k squarings per lane: the largest k for all, each lane keeping its value past its own k.
  Mask kv;
  std::memcpy(&kv, k, sizeof kv);
  for (int s = 0; s < k_max; ++s) {
    Lanes sq[kC];
    square_lanes<N>(gl, sq);
    const Mask take = Mask{} + s < kv;
    for (int i = 0; i < kC; ++i) gl[i] = select(take, sq[i], gl[i]);
  }
  Lanes vdc;
  std::memcpy(&vdc, dc, sizeof vdc);
  for (int i = 0; i < kC; ++i) out[i] = gl[i] * vdc;
}

// exp_visibility's clamp (exp_log.cpp) on kBatch lanes.
template <int N>
void clamp_visibility_lanes(Lanes* v) {
  constexpr int kC = N * N;
  const float full = 1.0f / kY0;
  const Mask finite0 = finite(v[0]);
  for (int i = 0; i < kC; ++i) v[i] = select(finite0, v[i], Lanes{});
  v[0] = select(v[0] < 0.0f, Lanes{}, select(full < v[0], splat(full), v[0]));
  Lanes rest2{};
  for (int i = 1; i < kC; ++i) rest2 += v[i] * v[i];
  const Lanes spare = full * v[0] - v[0] * v[0];
  const Lanes max_rest2 = select(0.0f < spare, spare, Lanes{});
  const Mask fine = rest2 <= max_rest2;
  if (!(~fine[0] | ~fine[1] | ~fine[2] | ~fine[3] | ~fine[4] | ~fine[5] | ~fine[6] | ~fine[7]))
    return;  // every lane within bounds (the usual case)
  const Lanes ratio = max_rest2 / rest2;
  alignas(32) float r[kBatch];
  std::memcpy(r, &ratio, sizeof r);
  for (float& x : r) x = std::sqrt(std::max(x, 0.0f));  // the lanes that use it have x >= 0
  Lanes root;
  std::memcpy(&root, r, sizeof root);
  const Lanes scale = select((rest2 > 0.0f) & finite(rest2), root, Lanes{});
  for (int i = 1; i < kC; ++i)
    v[i] = select(fine, v[i], select(finite(v[i]), v[i] * scale, Lanes{}));
}

template <int N>
void rotate_zh_lanes(const Zonal<N>& z, const DirBatch& axis, Lanes* out) {
  Lanes x, y, zz;
  std::memcpy(&x, axis.x, sizeof x);
  std::memcpy(&y, axis.y, sizeof y);
  std::memcpy(&zz, axis.z, sizeof zz);
  Lanes basis[N * N];
  basis_lanes<N>(x, y, zz, basis);
  for (int l = 0; l < N; ++l) {
    const float k = std::sqrt(4 * std::numbers::pi_v<float> / static_cast<float>(2 * l + 1)) * z[l];
    for (int m = -l; m <= l; ++m) out[index(l, m)] = k * basis[index(l, m)];
  }
}

template <int N>
void check_sizes(std::size_t count, std::size_t a, std::size_t b, std::size_t c, const char* what) {
  if (a != count || b != count || (c != 0 && c != count))
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(count) +
                                " inputs but sizes " + std::to_string(a) + ", " +
                                std::to_string(b) + ", " + std::to_string(c));
}
}  // namespace

template <int N>
void exp_hyb_batch(const CoeffsBatch<N>& f, CoeffsBatch<N>& out, float ol_norm) {
  Lanes in[N * N], v[N * N];
  load<N>(f, in);
  exp_hyb_lanes<N>(in, v, ol_norm);
  store<N>(v, out);
}

template <int N>
void exp_visibility_batch(const CoeffsBatch<N>& log_visibility, CoeffsBatch<N>& out) {
  Lanes in[N * N], v[N * N];
  load<N>(log_visibility, in);
  exp_hyb_lanes<N>(in, v, kHybOlNorm);
  clamp_visibility_lanes<N>(v);
  store<N>(v, out);
}

template <int N>
void product_batch(const CoeffsBatch<N>& f, const CoeffsBatch<N>& h, CoeffsBatch<N>& out) {
  Lanes a[N * N], b[N * N], p[N * N];
  load<N>(f, a);
  load<N>(h, b);
  product_lanes<N>(a, b, p);
  store<N>(p, out);
}

template <int N>
void rotate_zh_batch(const Zonal<N>& z, const DirBatch& axis, CoeffsBatch<N>& out) {
  Lanes r[N * N];
  rotate_zh_lanes<N>(z, axis, r);
  store<N>(r, out);
}

template <int N>
void shade_zh_batch(const CoeffsRgb<N>& radiance, const Zonal<N>& lobe, const CoeffsBatch<N>& v,
                    const DirBatch& normal, float (&e)[3][kBatch]) {
  Lanes vis[N * N], rotated[N * N], transfer[N * N];
  load<N>(v, vis);
  rotate_zh_lanes<N>(lobe, normal, rotated);
  product_lanes<N>(vis, rotated, transfer);
  for (int c = 0; c < 3; ++c) {
    Lanes s{};
    for (int i = 0; i < N * N; ++i) s += radiance[c][i] * transfer[i];  // as sh::dot
    std::memcpy(e[c], &s, sizeof s);
  }
}

template <int N>
void evaluate_batch(const Coeffs<N>& f, std::span<const glm::vec3> dirs, std::span<float> out) {
  check_sizes<N>(dirs.size(), out.size(), out.size(), 0, "evaluate_batch");
  for (std::size_t first = 0; first < dirs.size(); first += kBatch) {
    const int lanes = static_cast<int>(std::min<std::size_t>(kBatch, dirs.size() - first));
    DirBatch d;
    for (int l = 0; l < kBatch; ++l) d.set(l, l < lanes ? dirs[first + l] : glm::vec3(0, 0, 1));
    Lanes x, y, z, basis[N * N];
    std::memcpy(&x, d.x, sizeof x);
    std::memcpy(&y, d.y, sizeof y);
    std::memcpy(&z, d.z, sizeof z);
    basis_lanes<N>(x, y, z, basis);
    Lanes s{};
    for (int i = 0; i < N * N; ++i) s += f[i] * basis[i];  // as sh::evaluate
    alignas(32) float v[kBatch];
    std::memcpy(v, &s, sizeof v);
    for (int l = 0; l < lanes; ++l) out[first + l] = v[l];
  }
}

template <int N>
void exp_visibility_batch(std::span<const Coeffs<N>> log_visibility, std::span<Coeffs<N>> out) {
  check_sizes<N>(log_visibility.size(), out.size(), out.size(), 0, "exp_visibility_batch");
  CoeffsBatch<N> in{}, v;
  for (std::size_t first = 0; first < log_visibility.size(); first += kBatch) {
    const int lanes =
        static_cast<int>(std::min<std::size_t>(kBatch, log_visibility.size() - first));
    for (int l = 0; l < kBatch; ++l) in.set(l, l < lanes ? log_visibility[first + l] : Coeffs<N>{});
    exp_visibility_batch<N>(in, v);
    for (int l = 0; l < lanes; ++l) out[first + l] = v.get(l);
  }
}

template <int N>
void irradiance_batch(const CoeffsRgb<N>& radiance, const Zonal<N>& lobe,
                      std::span<const Coeffs<N>> log_visibility, std::span<const glm::vec3> normals,
                      std::span<glm::vec3> irradiance, std::span<Coeffs<N>> visibility) {
  check_sizes<N>(log_visibility.size(), normals.size(), irradiance.size(), visibility.size(),
                 "irradiance_batch");
  CoeffsBatch<N> in{}, v;
  DirBatch n{};
  float e[3][kBatch];
  for (std::size_t first = 0; first < log_visibility.size(); first += kBatch) {
    const int lanes =
        static_cast<int>(std::min<std::size_t>(kBatch, log_visibility.size() - first));
    for (int l = 0; l < kBatch; ++l) {
      in.set(l, l < lanes ? log_visibility[first + l] : Coeffs<N>{});
      n.set(l, l < lanes ? normals[first + l] : glm::vec3(0, 0, 1));
    }
    exp_visibility_batch<N>(in, v);
    shade_zh_batch<N>(radiance, lobe, v, n, e);
    for (int l = 0; l < lanes; ++l) {
      irradiance[first + l] = glm::vec3(e[0][l], e[1][l], e[2][l]);
      if (!visibility.empty()) visibility[first + l] = v.get(l);
    }
  }
}

#define PENUMBRA_BATCH_INSTANTIATE(N)                                                              \
  template void exp_hyb_batch<N>(const CoeffsBatch<N>&, CoeffsBatch<N>&, float);                   \
  template void exp_visibility_batch<N>(const CoeffsBatch<N>&, CoeffsBatch<N>&);                   \
  template void product_batch<N>(const CoeffsBatch<N>&, const CoeffsBatch<N>&, CoeffsBatch<N>&);   \
  template void rotate_zh_batch<N>(const Zonal<N>&, const DirBatch&, CoeffsBatch<N>&);             \
  template void shade_zh_batch<N>(const CoeffsRgb<N>&, const Zonal<N>&, const CoeffsBatch<N>&,     \
                                  const DirBatch&, float(&)[3][kBatch]);                           \
  template void evaluate_batch<N>(const Coeffs<N>&, std::span<const glm::vec3>, std::span<float>); \
  template void exp_visibility_batch<N>(std::span<const Coeffs<N>>, std::span<Coeffs<N>>);         \
  template void irradiance_batch<N>(const CoeffsRgb<N>&, const Zonal<N>&,                          \
                                    std::span<const Coeffs<N>>, std::span<const glm::vec3>,        \
                                    std::span<glm::vec3>, std::span<Coeffs<N>>);
PENUMBRA_BATCH_INSTANTIATE(2)
PENUMBRA_BATCH_INSTANTIATE(3)
PENUMBRA_BATCH_INSTANTIATE(4)
PENUMBRA_BATCH_INSTANTIATE(5)
PENUMBRA_BATCH_INSTANTIATE(6)
#undef PENUMBRA_BATCH_INSTANTIATE

}  // namespace penumbra::sh
