// Interpolation weights of a point in one cell of a probe cloud (data/probe_cloud.h).
//  - inner tetrahedron: the barycentric coordinates from the cell's transform ([Sukys14]
//    sec. 4.2), weight[i] for vertices[i];
//  - outer cell ([Cupisz12]): t solves det[p0 + t n0 - p, ...] = 0 (the cubic whose coefficients
//    the transform holds; evaluated in double relative to p0 here for precision far from the
//    origin), degree dropping to quadratic or linear when the hull normals make the leading
//    coefficients vanish (e.g. a flat hull face with equal normals); the weights are then the
//    barycentric coordinates of p on the moved triangle p_i + t n_i, weight[3] = 0.
//    When p is on the inner side of the hull triangle (no root t >= 0), weight[3] < 0 and is
//    the most negative: the walk steps to neighbours[3], the tetrahedron.
// Inside the cell every weight is >= 0 (up to rounding) and they sum to 1. A negative weight
// means p is outside the cell; the walk steps across the face of the most negative one.
// convex_weights() turns any weights into a convex combination (clamp, renormalise), so an
// interpolation at the hull edge or past it never goes black or overbright.
// Threading: pure functions of an immutable cloud.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

#include "penumbra/data/probe_cloud.h"

namespace penumbra::probe_cloud {

std::array<float, 4> cell_weights(const data::ProbeCloud& cloud, std::uint32_t cell,
                                  const glm::vec3& p);

// The smallest root t >= 0 of the outer cell's cubic at p (metres along the hull normals), or a
// negative value when p is on the inner side of the hull triangle. Exposed for tests.
double outer_cell_parameter(const data::ProbeCloud& cloud, std::uint32_t cell, const glm::vec3& p);

// Negative weights to 0, then divided by their sum (the largest gets 1 if all were <= 0).
// Inline: the walk calls it once per entity.
inline std::array<float, 4> convex_weights(const std::array<float, 4>& w) {
  std::array<float, 4> out{};
  float sum = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    out[i] = std::max(w[i], 0.0f);
    sum += out[i];
  }
  if (sum > 0) {
    for (float& v : out) v /= sum;
    return out;
  }
  const auto best = static_cast<std::size_t>(std::max_element(w.begin(), w.end()) - w.begin());
  out = {};
  out[best] = 1.0f;
  return out;
}

}  // namespace penumbra::probe_cloud
