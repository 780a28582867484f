// Log-SH wedges ([Giraud] sec. 4.1, eq. 18-23).
//
// Each slice vector v_k enters two wedges: as the left border of wedge k (rotated to phi_k) and
// as the right border of wedge k - 1 (rotated to phi_{k-1}). The constructor folds both into one
// (N*N) x N matrix per azimuth, G_k = R(phi_k) M_L + R(phi_{k-1}) M_R (M_lin = [M_L M_R]), so
// log_visibility is sum_k G_k v_k: N*N*N multiply-adds per azimuth. v_k is sh::nlp_log_slice,
// evaluated here eight azimuths at a time in float: v_l = log_eps sqrt((2l+1)/2) q_l(sin sigma)
// with q_0 = t + 1, q_l = (P_l+1(t) - P_l-1(t)) / (2l+1); the constant factors are folded into
// G_k and sin is a degree-11 Taylor polynomial (error < 1e-7 on [-pi/2, pi/2]).
#include "penumbra/systems/terrain_shadow/log_wedge.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string>

#include "penumbra/sh/projection.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/sh/zh.h"

#include "fast_math.h"
#include "lanes.h"

namespace penumbra::terrain_shadow {
namespace {

using detail::kHalfPi;

using detail::Lanes;  // lanes.h
using detail::load;
using detail::store;

// sin x for |x| <= pi/2: Taylor series to x^11 (truncation < 6e-8).
inline Lanes sin_poly(Lanes x) {
  const Lanes y = -(x * x);
  Lanes s = Lanes{} + 1.0f / 39916800;
  for (float c : {1.0f / 362880, 1.0f / 5040, 1.0f / 120, 1.0f / 6, 1.0f}) s = s * y + c;
  return s * x;
}

// Gauss-Legendre orders: in the polar angle the integrand is a trigonometric polynomial of
// degree <= 2N, in phi a product of a linear ramp and cos/sin(m phi): 24 and 16 points reach
// float precision (log_wedge_test.cpp checks M_lin against an independent projection).
constexpr int kPolarPoints = 24;
constexpr int kLogAzimuthPoints = 16;

// Nodes and weights on [-1, 1] (sh::SphereQuadrature's z nodes; its weights include 2 pi).
void gauss_legendre_nodes(int n, std::vector<double>& x, std::vector<double>& w) {
  const sh::SphereQuadrature q = sh::SphereQuadrature::gauss(n, 1);
  for (int i = 0; i < n; ++i) {
    x.push_back(q.directions[i].z);
    w.push_back(q.weights[i] / (2 * std::numbers::pi));
  }
}

}  // namespace

template <int N>
LogWedge<N>::LogWedge(int azimuths, float log_eps) : azimuths_(azimuths), log_eps_(log_eps) {
  if (azimuths < 3) {
    throw std::invalid_argument("LogWedge: " + std::to_string(azimuths) + " azimuths (need >= 3)");
  }
  if (!std::isfinite(log_eps) || log_eps >= 0) {
    throw std::invalid_argument("LogWedge: log_eps " + std::to_string(log_eps) +
                                " must be finite and < 0");
  }
  constexpr int kNN = N * N, kCols = 2 * N;
  const double dphi = 2 * std::numbers::pi / azimuths;
  std::vector<double> tx, tw, px, pw;
  gauss_legendre_nodes(kPolarPoints, tx, tw);
  gauss_legendre_nodes(kLogAzimuthPoints, px, pw);

  // Eq. 21-23: [M_lin]_ij = integral over the wedge of I_lin,j P^_j(cos theta) y_i, with
  // I_lin = (1 - alpha) for the left border's N columns and alpha for the right border's.
  std::vector<double> m(static_cast<std::size_t>(kNN) * kCols, 0.0);
  float y[kNN];
  for (std::size_t a = 0; a < px.size(); ++a) {
    const double alpha = 0.5 * (px[a] + 1), phi = alpha * dphi;
    for (std::size_t t = 0; t < tx.size(); ++t) {
      const double theta = 0.5 * std::numbers::pi * (tx[t] + 1), z = std::cos(theta),
                   s = std::sin(theta);
      const double weight = 0.5 * dphi * pw[a] * 0.5 * std::numbers::pi * tw[t] * s;
      sh::eval_basis<N>(glm::vec3(static_cast<float>(s * std::cos(phi)),
                                  static_cast<float>(s * std::sin(phi)), static_cast<float>(z)),
                        y);
      const std::array<float, N> p = sh::nlp_basis<N>(static_cast<float>(z));
      for (int i = 0; i < kNN; ++i) {
        for (int j = 0; j < N; ++j) {
          const double f = weight * p[j] * y[i];
          m[static_cast<std::size_t>(i) * kCols + j] += (1 - alpha) * f;
          m[static_cast<std::size_t>(i) * kCols + N + j] += alpha * f;
        }
      }
    }
  }
  m_lin_.assign(m.begin(), m.end());

  // G_k = R(phi_k) M_L + R(phi_{k-1}) M_R times the slices' constant factors, column-major per
  // azimuth, columns padded to whole 8-lane vectors.
  gather_.assign(static_cast<std::size_t>(azimuths) * N * kColumn, 0.0f);
  for (int k = 0; k < azimuths; ++k) {
    const float phi = static_cast<float>(dphi * k);
    const float phi_prev = static_cast<float>(dphi * ((k + azimuths - 1) % azimuths));
    for (int j = 0; j < N; ++j) {
      const double scale = log_eps * std::sqrt((2 * j + 1) / 2.0);
      sh::Coeffs<N> left, right;
      for (int i = 0; i < kNN; ++i) {
        left[i] = m_lin_[static_cast<std::size_t>(i) * kCols + j];
        right[i] = m_lin_[static_cast<std::size_t>(i) * kCols + N + j];
      }
      const sh::Coeffs<N> a = sh::rotate_z<N>(left, phi), b = sh::rotate_z<N>(right, phi_prev);
      float* col = gather_.data() + (static_cast<std::size_t>(k) * N + j) * kColumn;
      for (int i = 0; i < kNN; ++i) col[i] = static_cast<float>(scale * (a[i] + b[i]));
    }
  }
}

template <int N>
sh::Coeffs<N> LogWedge<N>::log_visibility(const float* angles) const {
  constexpr int kNN = N * N, kV = kColumn / kLanes;
  Lanes acc[kV] = {};
  const float* g = gather_.data();
  for (int k0 = 0; k0 < azimuths_; k0 += kLanes) {
    const int count = std::min(kLanes, azimuths_ - k0);
    float sigma[kLanes] = {};
    std::memcpy(sigma, angles + k0, count * sizeof(float));
    // Eq. 15-16 for eight slices: the integrals q_l of P_l over [-1, sin sigma].
    Lanes x = load(sigma);
    x = x > -kHalfPi ? x : -kHalfPi;  // NaN reads as -pi/2: nothing occludes
    x = x < kHalfPi ? x : kHalfPi;
    const Lanes t = sin_poly(x);
    Lanes p[N + 1];
    p[0] = Lanes{} + 1;
    p[1] = t;
    for (int l = 2; l <= N; ++l) {
      p[l] = (static_cast<float>(2 * l - 1) * t * p[l - 1] - static_cast<float>(l - 1) * p[l - 2]) /
             static_cast<float>(l);
    }
    float q[N][kLanes];
    store(q[0], t + 1);
    for (int l = 1; l < N; ++l) store(q[l], (p[l + 1] - p[l - 1]) / static_cast<float>(2 * l + 1));
    for (int e = 0; e < count; ++e) {
      for (int j = 0; j < N; ++j, g += kColumn) {
#pragma GCC unroll 8
        for (int v = 0; v < kV; ++v) acc[v] += q[j][e] * load(g + v * kLanes);
      }
    }
  }
  float flat[kColumn];
  std::memcpy(flat, acc, sizeof flat);
  sh::Coeffs<N> out;
  std::copy(flat, flat + kNN, out.begin());
  return out;
}

template class LogWedge<2>;
template class LogWedge<3>;
template class LogWedge<4>;
template class LogWedge<5>;
template class LogWedge<6>;

}  // namespace penumbra::terrain_shadow
