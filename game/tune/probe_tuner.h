// The probe cloud on a tune scene (docs/tune.md): a probe bake (probe_bake::bake_probe_cloud:
// placement, capture of the sky through the terrain and objects plus one bounce, validity,
// tetrahedralization) at each setting, its irradiance interpolated by ProbeTetWalk at
// TuneScene::probe_points free points (6 axis normals each) against the reference integrator's
// environment + one-bounce irradiance there (the placement accuracy tests' measure,
// tests/probe_bake/room_accuracy_points.h).
// Knobs, cheapest first: probes per side of the probe volume's longest horizontal side (3, 4,
// 6, 8, 11, 16, 22: the grid spacing is that side over (n - 1)), placement (grid, spawn and merge).
// Cost: the cloud's probe count (memory, bake time, and the walk's cache footprint; the walk
// itself costs the same per query whatever the count). ms: the bake's time.
// Threading: one thread calls the members; the bake and the reference use TBB inside.
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "greedy_search.h"
#include "penumbra/settings/tuned_settings.h"
#include "tune_common.h"
#include "tune_scene.h"

namespace penumbra::reference {
class Scene;
}

namespace penumbra::tune {

class ProbeTuner {
 public:
  ProbeTuner(const TuneScene& scene, const TuneOptions& options);
  ~ProbeTuner();

  const std::vector<Knob>& knobs() const { return knobs_; }
  settings::ProbeTuning tuning(const Config& config) const;
  // `tuning.probes_per_side` sets the spacing on this scene (its spacing field is ignored).
  Evaluation evaluate(const settings::ProbeTuning& tuning) const;
  std::size_t points() const { return points_.size(); }
  float side() const;  // the probe volume's longest horizontal side, metres

 private:
  const TuneScene& scene_;
  TuneOptions options_;
  std::vector<Knob> knobs_;
  std::unique_ptr<reference::Scene> traced_;
  std::vector<glm::vec3> points_;
  std::vector<glm::vec3> reference_;  // 6 per point
};

}  // namespace penumbra::tune
