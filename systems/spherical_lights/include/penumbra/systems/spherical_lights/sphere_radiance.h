// A spherical light's radiance as SH, from the diffuse reflection at its surface sample points
// ([Guerrero08] sec. 5.2).
//
// Eq. 9 projects the piecewise-constant function L(w) that takes, in the Voronoi cell of sample
// direction w_j, the value L_pj: Monte Carlo over N jittered stratified directions (N >> m).
// Eq. 10 precomputes, per cell, the basis sum Y_j = 4 pi / N * sum of y(w_k) over its directions,
// so each frame costs m multiply-adds per coefficient: L_S = sum_j L_pj Y_j. Directions with no
// point carry 0: the SL emits nothing there (reflector_samples.h).
// Eq. 11: the SL's radiance is the SH product of L_S and the albedo's SH c_S (projected the same
// way from the points' albedo), L^c = L_S * c.
//
// Threading: VoronoiCellSums is immutable after construction; the functions are pure.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"

namespace penumbra::spherical_lights {

template <int N>
class VoronoiCellSums {
 public:
  // `directions`: the m sample directions (unit); `strata`: N = strata^2 * 2 jittered directions
  // over the sphere (a strata x 2 strata grid in (cos theta, phi)), deterministic for `seed`.
  explicit VoronoiCellSums(std::span<const glm::vec3> directions, int strata = 64,
                           std::uint32_t seed = 1);

  int cells() const { return static_cast<int>(sums_.size()); }
  int directions() const { return total_; }                   // N
  const sh::Coeffs<N>& sum(int j) const { return sums_[j]; }  // Y_j, 4 pi / N included
  int count(int j) const { return counts_[j]; }               // N_j

  // [Guerrero08] eq. 10: sum_j values[j] Y_j, one RGB value per direction.
  sh::CoeffsRgb<N> project(std::span<const glm::vec3> values) const;

 private:
  std::vector<sh::Coeffs<N>> sums_;
  std::vector<int> counts_;
  int total_ = 0;
};

// [Guerrero08] eq. 11: L^c = L_S * c_S, per channel, by the SH product (sh/product.h).
template <int N>
sh::CoeffsRgb<N> albedo_product(const sh::CoeffsRgb<N>& radiance, const sh::CoeffsRgb<N>& albedo);

}  // namespace penumbra::spherical_lights
