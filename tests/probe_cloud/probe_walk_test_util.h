// Shared by the traversal tests: clouds (random, grid, rod) with random or affine SH, and the
// brute-force locate the walk is checked against.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/probe_cloud.h"
#include "penumbra/systems/probe_cloud/cell_weights.h"
#include "penumbra/systems/probe_cloud/probe_cloud_build.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

namespace penumbra::probe_cloud::test {

inline std::vector<glm::vec3> random_points(std::size_t n, float size, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, size);
  std::vector<glm::vec3> p(n);
  for (glm::vec3& q : p) q = {u(rng), u(rng), u(rng)};
  return p;
}

inline std::vector<glm::vec3> grid_points(int nx, int ny, int nz, float spacing) {
  std::vector<glm::vec3> p;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        p.push_back(glm::vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)) *
                    spacing);
  return p;
}

// Random SH: a positive DC term (0.5..1.5) per channel and smaller higher coefficients.
inline std::vector<float> random_sh(std::size_t probes, int bands, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dc(0.5f, 1.5f), rest(-0.3f, 0.3f);
  const std::size_t n = static_cast<std::size_t>(bands * bands);
  std::vector<float> sh(probes * 3 * n);
  for (std::size_t i = 0; i < sh.size(); ++i) sh[i] = (i % n == 0) ? dc(rng) : rest(rng);
  return sh;
}

// The affine field every coefficient follows in affine_sh: f(p) = a . p + b, per (channel, i).
inline float affine_coeff(const glm::vec3& p, std::size_t ch, std::size_t i) {
  const float k = static_cast<float>(ch * 16 + i);
  const glm::vec3 a(0.01f * (k + 1), -0.02f * (k - 3), 0.015f * std::cos(k));
  return glm::dot(a, p) + 1.0f + 0.1f * k;
}

inline std::vector<float> affine_sh(const std::vector<glm::vec3>& points, int bands) {
  const std::size_t n = static_cast<std::size_t>(bands * bands);
  std::vector<float> sh;
  for (const glm::vec3& p : points)
    for (std::size_t ch = 0; ch < 3; ++ch)
      for (std::size_t i = 0; i < n; ++i) sh.push_back(affine_coeff(p, ch, i));
  return sh;
}

inline std::shared_ptr<const data::ProbeCloud> make_cloud(const std::vector<glm::vec3>& points,
                                                          const std::vector<float>& sh,
                                                          int bands = 3) {
  ProbeCloudBuildSettings settings;
  settings.bands = bands;
  return std::make_shared<const data::ProbeCloud>(build_probe_cloud(points, sh, settings));
}

inline float min_weight(const std::array<float, 4>& w) {
  return std::min(std::min(w[0], w[1]), std::min(w[2], w[3]));
}

// The cell whose smallest weight at p is largest (all >= 0 in the cell holding p).
inline std::int32_t brute_force_cell(const data::ProbeCloud& cloud, const glm::vec3& p,
                                     float* best_min = nullptr) {
  std::int32_t best = -1;
  float bm = -std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < cloud.cells.size(); ++i) {
    const float m = min_weight(cell_weights(cloud, static_cast<std::uint32_t>(i), p));
    if (m > bm) {
      bm = m;
      best = static_cast<std::int32_t>(i);
    }
  }
  if (best_min) *best_min = bm;
  return best;
}

inline ProbeSh interpolate_cell(const data::ProbeCloud& cloud, std::int32_t cell,
                                const glm::vec3& p) {
  std::array<float, 4> w = convex_weights(cell_weights(cloud, static_cast<std::uint32_t>(cell), p));
  const data::ProbeCell& c = cloud.cells[static_cast<std::size_t>(cell)];
  if (c.outer()) w[3] = 0;
  return interpolate_probe_sh(cloud, c.vertices, w);
}

template <std::size_t kN>  // sh::CoeffsRgb of any bands (ProbeSh: 4, ProbeLighting: 3)
float max_abs_diff(const std::array<std::array<float, kN>, 3>& a,
                   const std::array<std::array<float, kN>, 3>& b) {
  float d = 0;
  for (std::size_t ch = 0; ch < 3; ++ch)
    for (std::size_t i = 0; i < a[ch].size(); ++i) d = std::max(d, std::fabs(a[ch][i] - b[ch][i]));
  return d;
}

}  // namespace penumbra::probe_cloud::test
