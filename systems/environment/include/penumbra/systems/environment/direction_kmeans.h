// Weighted k-means for light-source detection ([Ambrosj16] sec. 4.1, Algorithm 1's K-Means):
// Lloyd iterations in R^3 with squared Euclidean distance, on unit direction vectors (Penumbra's
// default) or on pixel coordinates (x, y, 0) (003's 2D distance).
//
// Contract: deterministic. Seeding is farthest-point (maximin): the first mean is points[first],
// each next one the point farthest from the means so far (ties: the lowest index); no random
// numbers, so the same input gives the same clusters on every machine and thread count.
// k is clamped to [1, points.size()]; weights must be >= 0 (a point's pull on its mean, here
// the texel's solid angle). Iterates until no point changes cluster or max_iterations.
// Throws std::invalid_argument on empty points, a weights size mismatch, first out of range,
// or k < 1. Threading: a pure function; independent calls may run concurrently.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::environment {

struct KMeansResult {
  std::vector<glm::vec3> means;  // per cluster: the weighted mean of its points
  std::vector<double> weights;   // per cluster: the sum of its points' weights
  std::vector<int> assignment;   // per point: its cluster
  int iterations = 0;            // Lloyd steps run
};

KMeansResult kmeans(const std::vector<glm::vec3>& points, const std::vector<float>& weights, int k,
                    std::size_t first, int max_iterations);

}  // namespace penumbra::environment
