// Shared plumbing of the estimators (private): input checks, ray offsets, the parallel loop.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "penumbra/data/finite.h"
#include "penumbra/reference/estimators.h"

namespace penumbra::reference::detail {

// Salts keep the random streams of different estimators apart for one (seed, receiver).
enum Salt : std::uint64_t {
  kEnvironmentSalt = 1,
  kLightSalt = 2,
  kVisibilitySalt = 3,
  kBounceSalt = 4
};

// MIS weight of the strategy with density `p` against the other one's `q`, equal sample counts
// (Veach 1997, sec. 9.2.2-9.2.3).
inline double mis_weight(MisHeuristic h, double p, double q) {
  if (h == MisHeuristic::kBalance) return p / (p + q);
  return p * p / (p * p + q * q);
}

using data::finite;

inline constexpr float kInf = std::numeric_limits<float>::infinity();

// No light at all: every channel at or below zero.
inline bool black(const glm::vec3& v) {
  return v.x <= 0 && v.y <= 0 && v.z <= 0;
}

inline void check_options(const SamplingOptions& o, const char* fn) {
  if (o.samples < 1) {
    throw std::invalid_argument(std::string(fn) + ": samples = " + std::to_string(o.samples) +
                                " must be >= 1");
  }
  if (!std::isfinite(o.ray_offset) || o.ray_offset < 0) {
    throw std::invalid_argument(std::string(fn) + ": ray_offset must be finite and >= 0");
  }
}

inline void check_albedo(const std::optional<glm::vec3>& a, const char* fn) {
  if (a && (!finite(*a) || a->x < 0 || a->y < 0 || a->z < 0)) {
    throw std::invalid_argument(std::string(fn) + ": albedo must be finite and >= 0");
  }
}

// Throws for a non-finite position or a zero / non-finite normal (zero allowed if asked).
inline void check_receivers(std::span<const Receiver> receivers, bool allow_zero_normal,
                            const char* fn) {
  for (std::size_t i = 0; i < receivers.size(); ++i) {
    const Receiver& r = receivers[i];
    const std::string what = std::string(fn) + ": receivers[" + std::to_string(i) + "]";
    if (!finite(r.position)) throw std::invalid_argument(what + ": position is not finite");
    if (!finite(r.normal)) throw std::invalid_argument(what + ": normal is not finite");
    const float len2 = glm::dot(r.normal, r.normal);
    if (!(len2 > 0) && !allow_zero_normal) {
      throw std::invalid_argument(what + ": normal is zero");
    }
    if (!std::isfinite(len2)) throw std::invalid_argument(what + ": normal is too long");
  }
}

// Unit normal (or zero) and the ray origin p + offset * n (estimators.h, "Ray offsets").
struct Shading {
  glm::vec3 n;
  glm::vec3 origin;
};
inline Shading shading(const Scene& scene, const Receiver& r, float ray_offset) {
  const float len2 = glm::dot(r.normal, r.normal);
  const glm::vec3 n = len2 > 0 ? r.normal / std::sqrt(len2) : glm::vec3(0.0f);
  float offset = ray_offset;
  if (!(offset > 0)) {
    const float p = std::fmax(std::fabs(r.position.x),
                              std::fmax(std::fabs(r.position.y), std::fabs(r.position.z)));
    offset = 1e-5f * std::fmax(scene.extent(), p);
  }
  return {n, r.position + offset * n};
}

// f(i) for every receiver index, in parallel; each index is independent of the others.
template <class F>
void for_each_receiver(std::size_t count, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) f(i);
                    });
}

}  // namespace penumbra::reference::detail
