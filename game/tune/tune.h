// `./penumbra tune` (docs/tune.md): per system, greedy_search over its tuner's knobs on one
// scene, the chosen configurations gathered into a settings file's values; and the same
// configurations measured again on another scene (the held-out check, tests/tune).
// Systems searched: terrain (TerrainTuner), blockers (BlockerTuner), spherical lights
// (SphericalLightTuner), probes (ProbeTuner).
// Threading: one thread; the systems and the reference use TBB inside.
#pragma once

#include <functional>
#include <string>

#include "greedy_search.h"
#include "penumbra/settings/tuned_settings.h"
#include "tune_common.h"
#include "tune_scene.h"

namespace penumbra::tune {

// After each evaluation (and once, reference = true, before a system's reference is computed).
struct ProgressEvent {
  std::string system;
  bool reference = false;
  int evaluations = 0;  // so far in this system
  int grid = 0;         // its full grid
  std::string config;   // the configuration just evaluated (describe())
  Evaluation eval;
};
using TuneProgress = std::function<void(const ProgressEvent&)>;

settings::TunedSettings run_tune(const TuneScene& scene, double budget, const TuneOptions& options,
                                 const TuneProgress& progress = {});

// The error of each tuned system's configuration in `s` on `scene` (result.error and ms
// replaced; `met` against s.budget); untuned systems are left as they are.
settings::TunedSettings evaluate_settings(const TuneScene& scene, const settings::TunedSettings& s,
                                          const TuneOptions& options);

}  // namespace penumbra::tune
