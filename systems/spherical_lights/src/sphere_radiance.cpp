#include "penumbra/systems/spherical_lights/sphere_radiance.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "penumbra/sh/product.h"

namespace penumbra::spherical_lights {

template <int N>
VoronoiCellSums<N>::VoronoiCellSums(std::span<const glm::vec3> directions, int strata,
                                    std::uint32_t seed) {
  if (directions.empty()) throw std::invalid_argument("VoronoiCellSums: no directions");
  if (strata < 1) throw std::invalid_argument("VoronoiCellSums: strata must be >= 1");
  sums_.assign(directions.size(), sh::Coeffs<N>{});
  counts_.assign(directions.size(), 0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const int rows = strata, cols = 2 * strata;
  total_ = rows * cols;
  const float weight = 4.0f * 3.14159265358979f / static_cast<float>(total_);  // eq. 9's 4 pi / N
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      // [Guerrero08] eq. 9: jittered stratification, uniform in (cos theta, phi).
      const float z = 1.0f - 2.0f * (static_cast<float>(r) + u01(rng)) / static_cast<float>(rows);
      const float phi =
          2.0f * 3.14159265358979f * (static_cast<float>(c) + u01(rng)) / static_cast<float>(cols);
      const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const glm::vec3 w(s * std::cos(phi), s * std::sin(phi), z);
      std::size_t best = 0;
      float best_dot = -2;
      for (std::size_t j = 0; j < directions.size(); ++j) {
        const float d = glm::dot(w, directions[j]);
        if (d > best_dot) best_dot = d, best = j;
      }
      const sh::Coeffs<N> y = sh::eval_basis<N>(w);
      for (int i = 0; i < N * N; ++i) sums_[best][i] += weight * y[i];
      ++counts_[best];
    }
  }
}

template <int N>
sh::CoeffsRgb<N> VoronoiCellSums<N>::project(std::span<const glm::vec3> values) const {
  if (values.size() != sums_.size()) {
    throw std::invalid_argument("VoronoiCellSums::project: " + std::to_string(values.size()) +
                                " values for " + std::to_string(sums_.size()) + " cells");
  }
  sh::CoeffsRgb<N> out{};
  for (std::size_t j = 0; j < sums_.size(); ++j) {
    const glm::vec3 v = values[j];
    if (v.x == 0 && v.y == 0 && v.z == 0) continue;
    for (int i = 0; i < N * N; ++i) {  // [Guerrero08] eq. 10
      out[0][i] += v.x * sums_[j][i];
      out[1][i] += v.y * sums_[j][i];
      out[2][i] += v.z * sums_[j][i];
    }
  }
  return out;
}

template <int N>
sh::CoeffsRgb<N> albedo_product(const sh::CoeffsRgb<N>& radiance, const sh::CoeffsRgb<N>& albedo) {
  sh::CoeffsRgb<N> out;
  for (int c = 0; c < 3; ++c) out[c] = sh::product<N>(radiance[c], albedo[c]);  // eq. 11
  return out;
}

#define PENUMBRA_INSTANTIATE(N)      \
  template class VoronoiCellSums<N>; \
  template sh::CoeffsRgb<N> albedo_product<N>(const sh::CoeffsRgb<N>&, const sh::CoeffsRgb<N>&);
PENUMBRA_INSTANTIATE(3)
PENUMBRA_INSTANTIATE(4)
PENUMBRA_INSTANTIATE(5)
#undef PENUMBRA_INSTANTIATE

}  // namespace penumbra::spherical_lights
