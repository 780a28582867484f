// LightHorizonMarch: the horizon from a texel along one plane direction (the light's azimuth,
// or a few across its cap), for the spherical lights' cap shading with
// TerrainShadowConfig::cap_method kMarch (cap_transfer.h), by the thesis's pyramid march:
// horizon_march.h for one direction per call ([Meier13] eq. 4.5-4.14, 4.22-4.25: sample
// distances, level choice eq. 4.14, elevation eq. 4.5-4.6 with the receiver at level 0,
// uniform cubic B-spline maximum over knots and mid-points, 1/6 2/3 1/6 and 1/48 23/48 23/48
// 1/48, and the spline at the light's own distance). For an azimuth 2 pi k / n_phi it gives
// what march_horizons gives (to 1e-6 rad, light_shading_test.cpp). Scalar, O(log d) samples
// per call.
//
// Threading: const members may run concurrently.
#pragma once

#include <vector>

#include <glm/vec2.hpp>

#include "penumbra/systems/terrain_shadow/height_pyramid.h"
#include "penumbra/systems/terrain_shadow/horizon_march.h"

namespace penumbra::terrain_shadow {

// Horizons along arbitrary directions from a built pyramid (see above).
class LightHorizonMarch {
 public:
  // The pyramid must stay alive and unchanged while this is used. Throws
  // std::invalid_argument for an unbuilt pyramid or a bad level offset.
  LightHorizonMarch(const HeightPyramid& pyramid, const MarchParams& march);

  // Elevation (radians, may be negative) of the horizon from texel (x, y) along the unit plane
  // direction `dir`, using terrain up to plane distance `limit` cells (the light's; eq. 4.24):
  // the samples up to the first one beyond `limit`, the spline's maximum up to `limit` (eq.
  // 4.25). No sample in range (limit < 1 cell, or the ray leaves the field at once): -pi/2.
  float horizon(int x, int y, glm::vec2 dir, float limit) const;

  int samples() const { return static_cast<int>(d_.size()); }

 private:
  const HeightPyramid* pyramid_;
  std::vector<float> d_;             // sample distances in cells (d_0 = 1, d_{i+1} = d_i + sr^i)
  std::vector<float> inv_metres_;    // 1 / (d_i * cell_size)
  std::vector<const float*> level_;  // level data read by sample i (eq. 4.14)
};

}  // namespace penumbra::terrain_shadow
