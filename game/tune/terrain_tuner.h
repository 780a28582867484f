// The terrain shadow system on a tune scene (docs/tune.md): TerrainShadowing's environment
// irradiance at every stride-th texel against the reference integrator's (engine/reference:
// the field, a ground plane at its lowest height 1000 times its extent wide, the sky), as the
// accuracy tests set it up (tests/terrain_shadow/terrain_reference.h, MODELLING NOTE).
// The sky as the system shades it: key lights + the rest in SH (sky_split.h).
// Knobs, cheapest first: horizon (march with pyramid step 4, 2; the exact sweep), azimuths
// (4, 8, 16, 32), SH bands (3..6). Cost: the measured time of update() + shade_environment()
// (fastest of TuneOptions::timing_reps).
// Threading: one thread calls the members; the reference and the method use TBB inside.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "greedy_search.h"
#include "penumbra/settings/tuned_settings.h"
#include "sky_split.h"
#include "tune_common.h"
#include "tune_scene.h"

namespace penumbra::tune {

class TerrainTuner {
 public:
  // Computes the reference (the slow part).
  TerrainTuner(const TuneScene& scene, const TuneOptions& options);

  const std::vector<Knob>& knobs() const { return knobs_; }
  settings::TerrainTuning tuning(const Config& config) const;
  Evaluation evaluate(const settings::TerrainTuning& tuning) const;
  std::size_t receivers() const { return texels_.size(); }

 private:
  const TuneScene& scene_;
  TuneOptions options_;
  SplitSky sky_;
  std::vector<Knob> knobs_;
  std::vector<std::size_t> texels_;
  std::vector<glm::vec3> reference_;
};

}  // namespace penumbra::tune
