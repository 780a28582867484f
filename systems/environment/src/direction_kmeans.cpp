#include "penumbra/systems/environment/direction_kmeans.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace penumbra::environment {

namespace {

float distance2(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return glm::dot(d, d);
}

}  // namespace

KMeansResult kmeans(const std::vector<glm::vec3>& points, const std::vector<float>& weights, int k,
                    std::size_t first, int max_iterations) {
  if (points.empty()) throw std::invalid_argument("kmeans: no points");
  if (weights.size() != points.size()) {
    throw std::invalid_argument("kmeans: " + std::to_string(weights.size()) + " weights for " +
                                std::to_string(points.size()) + " points");
  }
  if (first >= points.size()) {
    throw std::invalid_argument("kmeans: first seed " + std::to_string(first) +
                                " out of range for " + std::to_string(points.size()) + " points");
  }
  if (k < 1) throw std::invalid_argument("kmeans: k = " + std::to_string(k) + " < 1");
  const std::size_t m = points.size();
  const std::size_t clusters = std::min(static_cast<std::size_t>(k), m);

  KMeansResult r;
  // Farthest-point seeding (deterministic).
  r.means.push_back(points[first]);
  std::vector<float> nearest(m);
  for (std::size_t i = 0; i < m; ++i) nearest[i] = distance2(points[i], points[first]);
  while (r.means.size() < clusters) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < m; ++i)
      if (nearest[i] > nearest[best]) best = i;
    if (nearest[best] <= 0.0f) break;  // fewer distinct points than clusters
    r.means.push_back(points[best]);
    for (std::size_t i = 0; i < m; ++i)
      nearest[i] = std::min(nearest[i], distance2(points[i], points[best]));
  }
  const std::size_t c = r.means.size();
  r.assignment.assign(m, -1);
  r.weights.assign(c, 0.0);
  std::vector<glm::dvec3> sums(c);
  for (int it = 0; it < std::max(1, max_iterations); ++it) {
    bool changed = false;
    for (std::size_t i = 0; i < m; ++i) {
      int best = 0;
      float best_d = std::numeric_limits<float>::infinity();
      for (std::size_t j = 0; j < c; ++j) {
        const float d = distance2(points[i], r.means[j]);
        if (d < best_d) {
          best_d = d;
          best = static_cast<int>(j);
        }
      }
      if (r.assignment[i] != best) {
        r.assignment[i] = best;
        changed = true;
      }
    }
    std::fill(sums.begin(), sums.end(), glm::dvec3(0.0));
    std::fill(r.weights.begin(), r.weights.end(), 0.0);
    for (std::size_t i = 0; i < m; ++i) {
      const auto j = static_cast<std::size_t>(r.assignment[i]);
      sums[j] += static_cast<double>(weights[i]) * glm::dvec3(points[i]);
      r.weights[j] += weights[i];
    }
    for (std::size_t j = 0; j < c; ++j)
      if (r.weights[j] > 0) r.means[j] = glm::vec3(sums[j] / r.weights[j]);
    r.iterations = it + 1;
    if (!changed) break;
  }
  return r;
}

}  // namespace penumbra::environment
