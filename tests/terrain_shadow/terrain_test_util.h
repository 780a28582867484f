// Shared by the terrain shadow unit tests: small fields and SH comparisons.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "penumbra/assets/height_field.h"
#include "penumbra/assets/procedural.h"
#include "penumbra/sh/basis.h"

namespace penumbra::terrain_shadow::test {

// fBm mountains on an n x n grid, 2 m cells (slopes up to about 40 degrees).
inline std::shared_ptr<const assets::HeightField> mountains(int n, std::uint64_t seed = 4) {
  return std::make_shared<assets::HeightField>(
      assets::procedural_scene("mountains", {n, 2.0f * n}, seed));
}

template <int N>
float max_abs_diff(const sh::Coeffs<N>& a, const sh::Coeffs<N>& b) {
  float d = 0;
  for (int i = 0; i < N * N; ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// n horizon angles drawn uniformly from [lo, hi].
inline std::vector<float> random_horizon(std::mt19937& rng, int n, float lo, float hi) {
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> a(n);
  for (float& x : a) x = u(rng);
  return a;
}

}  // namespace penumbra::terrain_shadow::test
