// SH exponential and shading for kBatch (8) coefficient vectors at once, structure of arrays:
// one AVX2 register holds coefficient i of eight receivers, so every step of the scalar
// functions runs on eight lanes. What BlockerAccumulation / ReceiverClusters do per receiver
// after the log-visibility sum (exp_visibility, then the product with the clamped cosine rotated
// to the normal and three dots), eight receivers per call.
//
// Same results as the scalar functions: the generated product / square / basis code is the same
// source instantiated on a GCC/Clang float vector (scripts/gen_sh_code.py), and the per-lane
// scalar steps (HYB's number of squarings k, the OL table, e^DC) call the scalar code itself.
// Each lane gets exactly its own k squarings: the batch runs the largest k and keeps a lane's
// previous value once its own count is reached (a blend, so a lane never sees another's data).
// Measured against the scalar functions (tests/sh/batch_test.cpp): within a few float ulps
// (the compiler may fuse multiply-adds differently in the two instantiations).
//
// Threading: pure functions of their arguments.
#pragma once

#include <cstddef>
#include <span>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/zh.h"

namespace penumbra::sh {

inline constexpr int kBatch = 8;

// kBatch coefficient vectors, structure of arrays: c[i][lane] is coefficient i of vector `lane`.
template <int N>
struct CoeffsBatch {
  alignas(32) float c[N * N][kBatch];

  void set(int lane, const Coeffs<N>& f) {
    for (int i = 0; i < N * N; ++i) c[i][lane] = f[i];
  }
  Coeffs<N> get(int lane) const {
    Coeffs<N> f;
    for (int i = 0; i < N * N; ++i) f[i] = c[i][lane];
    return f;
  }
};

// kBatch unit directions (normals), structure of arrays.
struct DirBatch {
  alignas(32) float x[kBatch], y[kBatch], z[kBatch];

  void set(int lane, const glm::vec3& d) {
    x[lane] = d.x;
    y[lane] = d.y;
    z[lane] = d.z;
  }
};

// Per lane: exp_hyb<N>(f, ol_norm), exp_visibility<N>(f) (exp_log.h).
template <int N>
void exp_hyb_batch(const CoeffsBatch<N>& f, CoeffsBatch<N>& out, float ol_norm = kHybOlNorm);
template <int N>
void exp_visibility_batch(const CoeffsBatch<N>& log_visibility, CoeffsBatch<N>& out);

// Per lane: product<N>(f, g) (product.h).
template <int N>
void product_batch(const CoeffsBatch<N>& f, const CoeffsBatch<N>& g, CoeffsBatch<N>& out);

// Per lane: rotate_zh<N>(z, axis[lane]) (rotation.h).
template <int N>
void rotate_zh_batch(const Zonal<N>& z, const DirBatch& axis, CoeffsBatch<N>& out);

// Per lane: transfer = product(v, rotate_zh(lobe, normal)), then e[c][lane] = dot(radiance[c],
// transfer) for the three channels: BlockerAccumulation::irradiance_from_log after the
// exponential (kProduct, no lights), lobe the clamped cosine.
template <int N>
void shade_zh_batch(const CoeffsRgb<N>& radiance, const Zonal<N>& lobe, const CoeffsBatch<N>& v,
                    const DirBatch& normal, float (&e)[3][kBatch]);

// out[k] = evaluate<N>(f, dirs[k]) (basis.h) for any number of unit directions, eight per step:
// the depth limit's evaluations of a receiver's sum at its blockers' axes. `out` has the size
// of `dirs` (else std::invalid_argument).
template <int N>
void evaluate_batch(const Coeffs<N>& f, std::span<const glm::vec3> dirs, std::span<float> out);

// Any number of receivers (array of structures in and out; a last partial batch is padded with
// zero lanes): v = exp_visibility(log_v), and the irradiance per receiver as shade_zh_batch.
// `visibility` may be empty (not wanted); else it has one entry per receiver, as `irradiance`
// and `normals`. Throws std::invalid_argument on other sizes.
template <int N>
void exp_visibility_batch(std::span<const Coeffs<N>> log_visibility, std::span<Coeffs<N>> out);
template <int N>
void irradiance_batch(const CoeffsRgb<N>& radiance, const Zonal<N>& lobe,
                      std::span<const Coeffs<N>> log_visibility, std::span<const glm::vec3> normals,
                      std::span<glm::vec3> irradiance, std::span<Coeffs<N>> visibility = {});

}  // namespace penumbra::sh
