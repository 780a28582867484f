#include "penumbra/systems/blocker_accumulation/clipped_log_cap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "penumbra/sh/product.h"

namespace penumbra::blocker_accumulation {

template <int N>
sh::Zonal<N> ClippedLogCap<N>::compute(float sin_angle, float clip) {
  const float s = std::clamp(sin_angle, 0.0f, 1.0f);
  // v = 1 - cap, projected to N bands.
  const sh::Zonal<N> cap = sh::zh_cap<N>(std::asin(s));
  sh::Coeffs<N> v{};
  v[0] = std::sqrt(4 * std::numbers::pi_v<float>) - cap[0];
  for (int l = 1; l < N; ++l) v[sh::index(l, 0)] = -cap[l];
  // M_v column by column: the truncated product of v with each basis function.
  // Dynamic-size matrices: one eigensolver for every N (fixed K x K ones unrolled it four
  // times, a minute of compile time); the table is built once, so speed here does not count.
  constexpr int K = N * N;
  Eigen::MatrixXd m(K, K);
  for (int j = 0; j < K; ++j) {
    sh::Coeffs<N> e{};
    e[j] = 1;
    const sh::Coeffs<N> col = sh::product<N>(v, e);
    for (int i = 0; i < K; ++i) m(i, j) = col[i];
  }
  m = 0.5 * (m + m.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
  const auto& lambda = eig.eigenvalues();
  const double floor = clip * std::max(lambda.maxCoeff(), 1e-30);  // [Ren06]: clipped eigenvalues
  Eigen::VectorXd log_lambda(K);
  for (int i = 0; i < K; ++i) log_lambda(i) = std::log(std::max(lambda(i), floor));
  const auto& u = eig.eigenvectors();
  // log M applied to sqrt(4 pi) e_0: sqrt(4 pi) U diag(log lambda) (row 0 of U).
  const Eigen::VectorXd out =
      std::sqrt(4 * std::numbers::pi) * (u * log_lambda.asDiagonal() * u.row(0).transpose());
  sh::Zonal<N> z{};
  for (int l = 0; l < N; ++l) z[l] = static_cast<float>(out(sh::index(l, 0)));
  return z;
}

template <int N>
ClippedLogCap<N>::ClippedLogCap(float clip, int entries) : clip_(clip) {
  if (!(clip > 0 && clip < 1))
    throw std::invalid_argument("clipped log cap: clip " + std::to_string(clip) +
                                " must be in (0, 1)");
  if (entries < 2)
    throw std::invalid_argument("clipped log cap: " + std::to_string(entries) +
                                " table entries, at least 2 needed");
  table_.resize(static_cast<std::size_t>(entries));
  // Entry i at cos(half-angle) = 1 - i / (entries - 1): smooth there (the eps cap is a
  // polynomial in it), where in sin it is steep near a blocked hemisphere.
  for (int i = 0; i < entries; ++i) {
    const float c = 1 - static_cast<float>(i) / static_cast<float>(entries - 1);
    table_[static_cast<std::size_t>(i)] = compute(std::sqrt(std::max(0.0f, 1 - c * c)), clip);
  }
  depth_ = sh::evaluate<N>(sh::zonal_to_sh<N>(table_.back()), glm::vec3(0, 0, 1));
}

template <int N>
sh::Zonal<N> ClippedLogCap<N>::log_zh(float sin_angle) const {
  const float s = std::clamp(sin_angle, 0.0f, 1.0f);
  const float x = (1 - std::sqrt(1 - s * s)) * static_cast<float>(table_.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(x), table_.size() - 2);
  const float t = x - static_cast<float>(i);
  sh::Zonal<N> z;
  for (int l = 0; l < N; ++l) z[l] = (1 - t) * table_[i][l] + t * table_[i + 1][l];
  return z;
}

template <int N>
void add_log_visibility(const BlockerView& v, const ClippedLogCap<N>& cap,
                        sh::Coeffs<N>& log_visibility) {
  if (!(v.weight > 0)) return;
  const sh::Zonal<N> z = cap.log_zh(v.sin_angle);
  float y[N * N];
  sh::eval_basis<N>(v.axis, y);
  static const std::array<float, N> kRotate = [] {  // ZH rotation: sqrt(4 pi / (2l + 1))
    std::array<float, N> r;
    for (int l = 0; l < N; ++l) r[l] = std::sqrt(4 * std::numbers::pi_v<float> / (2 * l + 1));
    return r;
  }();
  for (int l = 0; l < N; ++l) {
    const float k = v.weight * z[l] * kRotate[l];
    for (int m = -l; m <= l; ++m) log_visibility[sh::index(l, m)] += k * y[sh::index(l, m)];
  }
}

#define PENUMBRA_CLIPPED_LOG_INSTANTIATE(N) \
  template class ClippedLogCap<N>;          \
  template void add_log_visibility<N>(const BlockerView&, const ClippedLogCap<N>&, sh::Coeffs<N>&);
PENUMBRA_CLIPPED_LOG_INSTANTIATE(3)
PENUMBRA_CLIPPED_LOG_INSTANTIATE(4)
PENUMBRA_CLIPPED_LOG_INSTANTIATE(5)
PENUMBRA_CLIPPED_LOG_INSTANTIATE(6)
#undef PENUMBRA_CLIPPED_LOG_INSTANTIATE

}  // namespace penumbra::blocker_accumulation
