// The first pass of [Guerrero08] (sec. 5) for one object: the direct light its surface sample
// points reflect, turned into each spherical light's (SL's) radiance SH, and the SLs placed in
// the world for SphereLightGather.
//
//  - Sec. 5.1, eq. 3-8: the irradiance E_j at each sample point, shadowed by every sphere blocker
//    of the scene (the object's own included: its other SLs shadow its concave parts) and lit by
//    the environment SH and the local lights, is BlockerAccumulation::shade's (one log-SH sum and
//    one exponential per point). The reflected value without albedo is L_pj = E_j / pi.
//  - Sec. 5.2, eq. 10-11: L^c = (sum_j L_pj Y_j) * c, c the albedo SH from the same cells.
// Transforms: a rigid motion with uniform scale ([Guerrero08] sec. 7.1). Sample points and
// normals move with it; the radiance SH stays in the object's frame and receivers look it up
// through the inverse rotation (SphereLightSource::to_local).
//
// Threading: immutable after construction; update() and place() from any number of threads.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/spherical_lights/reflector_samples.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"
#include "penumbra/systems/spherical_lights/sphere_radiance.h"

namespace penumbra::spherical_lights {

// Where an object is: world = rotation * (scale * local) + translation.
struct ObjectPose {
  glm::mat3 rotation{1.0f};
  glm::vec3 translation{0.0f};
  float scale = 1;
};

template <int N>
class ReflectorLighting {
 public:
  // `directions`: the samples' geodesic directions (ReflectorSamples::directions).
  explicit ReflectorLighting(std::span<const glm::vec3> directions, int strata = 64);

  const VoronoiCellSums<N>& cells() const { return cells_; }

  // The albedo SH c of one SL (eq. 11's c_S), per channel.
  sh::CoeffsRgb<N> albedo_sh(const SphereSamples& sl) const;

  // Eq. 3-11 for every SL of `object` at `pose`: L^c per SL, in the object's frame.
  // `blockers` holds the scene's spheres and local lights; `environment` the distant radiance SH.
  // `extra_log`, when given, is more log-SH visibility for every point (the terrain's cast shadow
  // at the object, [Giraud] sec. 4.1, as blockers.shade adds it). `reflected_out`, when given,
  // receives L_pj (E / pi per channel) per SL and direction. `buried`, when given, says which
  // world points are inside solid ground (under a terrain's surface): those reflect nothing.
  std::vector<sh::CoeffsRgb<N>> update(
      const ReflectorSamples& object, const ObjectPose& pose,
      const blocker_accumulation::BlockerAccumulation<N>& blockers,
      const sh::CoeffsRgb<N>& environment,
      std::vector<std::vector<glm::vec3>>* reflected_out = nullptr,
      const sh::Coeffs<N>* extra_log = nullptr,
      const std::function<bool(const glm::vec3&)>& buried = {}) const;

  // The SLs of `object` at `pose` with their radiance (one per SL, from update()), tagged with
  // `object_id`, appended to `out`.
  static void place(const ReflectorSamples& object, const ObjectPose& pose,
                    std::span<const sh::CoeffsRgb<N>> radiance, std::uint32_t object_id,
                    std::vector<SphereLightSource<N>>& out);

 private:
  VoronoiCellSums<N> cells_;
};

}  // namespace penumbra::spherical_lights
