// The blocker accumulation system on a tune scene (docs/tune.md): each object's fitted sphere
// set (assets::fit_spheres, k-means) as blockers, BlockerAccumulation's environment irradiance
// at upward receivers on a grid under and around each object (at the height of the ground below
// it), against the reference integrator's with the objects' meshes themselves under the same
// sky. No terrain in either: the terrain's cast shadow is the terrain system's.
// The sky as the system shades it: key lights (their discs occluded by the blockers,
// key_light_visibility) + the rest in SH (sky_split.h).
// Knobs, cheapest first: spheres per object (4, 8, 16, 32, 64), epsilon (0.4, 0.3, 0.2, 0.1:
// [Giraud] fig. 7; no cost of its own), SH bands (3..6). Cost: the measured time of the
// receivers' irradiance() (fastest of TuneOptions::timing_reps).
// Threading: one thread calls the members (the sphere fits are cached inside).
#pragma once

#include <map>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "greedy_search.h"
#include "penumbra/data/sphere_set.h"
#include "penumbra/settings/tuned_settings.h"
#include "sky_split.h"
#include "tune_common.h"
#include "tune_scene.h"

namespace penumbra::tune {

class BlockerTuner {
 public:
  BlockerTuner(const TuneScene& scene, const TuneOptions& options);

  const std::vector<Knob>& knobs() const { return knobs_; }
  settings::BlockerTuning tuning(const Config& config) const;
  Evaluation evaluate(const settings::BlockerTuning& tuning) const;
  std::size_t receivers() const { return points_.size(); }

  // Every object's fitted set in world space, `count` spheres each (fitted once, cached).
  const std::vector<data::Sphere>& world_spheres(int count) const;

 private:
  const TuneScene& scene_;
  TuneOptions options_;
  SplitSky sky_;
  std::vector<Knob> knobs_;
  std::vector<glm::vec3> points_;  // receivers, normal +z
  std::vector<glm::vec3> reference_;
  mutable std::map<int, std::vector<data::Sphere>> fits_;
};

}  // namespace penumbra::tune
