// Occluded environment maps (OEMs, [Ambrosj16] sec. 4.1-4.3): for n detected sources, the 2^n
// SH projections of the map with each subset of the sources' texels blackened, at 3 bands (003's
// order 3, with the eq. 3.15 irradiance matrices) and at sh::kDefaultBands.
//
// Contract: set index = mask of the sources still in the map: bit j set = source j present
// (003's S, the sources that light a fragment). sets[2^n - 1] is the whole map, sets[0] the map
// with every source removed. The HDR radiance is projected as it is (no tone mapping, no
// (1 - loss) factor: the blackened texels already take the sources' energy out; see
// docs/environment.md). build_occluded_environment_maps throws std::invalid_argument when the
// detection does not belong to the map (size, texel out of range, a texel in two sources) or
// the map fails check_environment_map. Threading: pure functions; independent calls may run
// concurrently.
#pragma once

#include <array>
#include <vector>

#include <glm/mat4x4.hpp>

#include "penumbra/data/environment_map.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/environment/light_source_detection.h"

namespace penumbra::environment {

struct OccludedEnvironmentMaps {
  int source_count = 0;
  std::vector<sh::CoeffsRgb<3>> sh3;                 // 2^n sets, 3 bands (9 coefficients)
  std::vector<sh::CoeffsRgb<sh::kDefaultBands>> sh;  // 2^n sets, kDefaultBands
  double milliseconds = 0;                           // wall time of the build

  std::size_t set_count() const { return sh.size(); }
};

// One projection of the map with every source blackened (sh::project_equirect), plus one sparse
// projection per source of its own texels; each set is the first plus its present sources
// (projection is linear, so this equals projecting each blackened copy, 2^n times cheaper).
OccludedEnvironmentMaps build_occluded_environment_maps(const data::EnvironmentMap& map,
                                                        const LightSourceDetection& detection);

// The irradiance matrix M per colour channel ([Ambrosj16] eq. 3.15, Ramamoorthi and Hanrahan
// 2001): E(n) = (n, 1)^T M (n, 1) for a unit normal n, from a 3-band radiance set in
// penumbra/sh's basis (the same real basis without Condon-Shortley phase, so no sign changes).
std::array<glm::mat4, 3> irradiance_matrices(const sh::CoeffsRgb<3>& radiance);

}  // namespace penumbra::environment
