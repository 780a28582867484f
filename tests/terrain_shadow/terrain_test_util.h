// Shared by the terrain shadow unit tests: small fields and SH comparisons.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/constants.h"
#include "penumbra/assets/procedural.h"
#include "penumbra/data/height_field.h"
#include "penumbra/data/luminance.h"
#include "penumbra/sh/basis.h"

namespace penumbra::terrain_shadow {

using data::luminance;  // Rec. 709, as the refresh policies measure

}  // namespace penumbra::terrain_shadow

namespace penumbra::terrain_shadow::test {

// A flat field of w x h samples at height `value`, `cell` metres apart, named `source` (what
// error messages name).
inline data::HeightField flat_field(int w, int h, float value = 0.0f, float cell = 1.0f,
                                    std::string source = "flat") {
  data::HeightField f;
  f.width = w;
  f.height = h;
  f.cell_size = cell;
  f.heights.assign(static_cast<std::size_t>(w) * h, value);
  f.source = std::move(source);
  return f;
}
// The same, n x n, shared (what TerrainShadowing::update takes).
inline std::shared_ptr<const data::HeightField> shared_flat(int n, float value = 0.0f,
                                                            float cell = 1.0f) {
  return std::make_shared<data::HeightField>(flat_field(n, n, value, cell));
}

// fBm mountains on an n x n grid, 2 m cells (slopes up to about 40 degrees).
inline std::shared_ptr<const data::HeightField> mountains(int n, std::uint64_t seed = 4) {
  return std::make_shared<data::HeightField>(
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
