// The direct irradiance at a surface point as one unbiased sample: the environment by MIS as in
// irradiance.cpp, each spherical light by cone sampling as in lights.cpp (PBRT 3rd ed. sec.
// 14.5, next-event estimation). Shared by the one-bounce estimators (bounce.cpp, radiance_sh.cpp).
// Threading: pure; the caller owns `rng`.
#pragma once

#include <cstdint>

#include <glm/ext/vector_double3.hpp>
#include <glm/vec3.hpp>

#include "penumbra/reference/estimators.h"
#include "penumbra/reference/sampling.h"
#include "penumbra/reference/scene.h"

namespace penumbra::reference::detail {

struct DirectOptions {
  int samples = 4;  // directions per source (the environment: samples / 2 per MIS strategy)
  MisHeuristic heuristic = MisHeuristic::kPower;
  float ray_offset = 0;
};

// Unbiased estimate of the direct irradiance (environment + lights) at x, unit normal n, with
// o.samples directions per source; counts the shadow rays it casts.
glm::dvec3 direct_irradiance(const Scene& scene, const glm::vec3& x, const glm::vec3& n,
                             const DirectOptions& o, Pcg32& rng, std::uint32_t& rays);

}  // namespace penumbra::reference::detail
