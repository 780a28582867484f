// The spherical lights on a tune scene (docs/tune.md): each object's fitted sphere set (16
// spheres, the main job's boulders') as spherical lights re-emitting what the object's surface
// reflects (sample_reflector -> ReflectorLighting, pass 1, under the blockers -> SphereLightGather,
// pass 2), their one-bounce irradiance at the blockers' ground receivers (BlockerTuner's grid)
// against the reference integrator's one diffuse bounce off the objects' meshes
// (reference::indirect_irradiance, the same albedo, under the same sky), as
// tests/spherical_lights/spherical_light_accuracy_test.cpp measures it. 4 bands (the system's).
// Knobs, cheapest first: sample directions (geodesic frequency 1, 2, 3, 4: 12, 42, 92, 162 per
// SL), blocking (per object, per sphere), the horizon rule at the receivers (shrink, clip;
// EmitterHorizon), the hierarchy cut (gather: clusters_parents, clusters_leaves, receivers:
// SphereLightGather::shade(clusters) with SlHierarchy kParents / kLeaves at the default
// far_ratio, or irradiance() per receiver; [Guerrero08] sec. 7.3). Cost: the measured time of
// pass 1 + pass 2 (fastest of timing_reps; the clustered gather in a one-thread arena, as the
// per-receiver one runs on the caller's thread; clustering is done once and not timed).
// Threading: one thread calls the members (samples cached per frequency inside).
#pragma once

#include <map>
#include <vector>

#include <glm/vec3.hpp>

#include "greedy_search.h"
#include "penumbra/data/reflector_samples.h"
#include "penumbra/data/sphere_set.h"
#include "penumbra/settings/tuned_settings.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"
#include "tune_common.h"
#include "tune_scene.h"

namespace penumbra::tune {

class SphericalLightTuner {
 public:
  SphericalLightTuner(const TuneScene& scene, const TuneOptions& options);

  const std::vector<Knob>& knobs() const { return knobs_; }
  settings::SphericalLightTuning tuning(const Config& config) const;
  Evaluation evaluate(const settings::SphericalLightTuning& tuning) const;

 private:
  const std::vector<data::ReflectorSamples>& samples(int frequency) const;

  const TuneScene& scene_;
  TuneOptions options_;
  std::vector<Knob> knobs_;
  std::vector<std::vector<data::Sphere>> spheres_;         // per object, world frame
  std::vector<glm::vec3> points_;                          // receivers, normal +z
  std::vector<glm::vec3> reference_;                       // one-bounce irradiance
  spherical_lights::SlReceiverClusters leaves_, parents_;  // points_ clustered, per hierarchy
  mutable std::map<int, std::vector<data::ReflectorSamples>> samples_;
};

}  // namespace penumbra::tune
