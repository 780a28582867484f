#include "tune.h"

#include "blocker_tuner.h"
#include "greedy_search.h"
#include "probe_tuner.h"
#include "spherical_light_tuner.h"
#include "terrain_tuner.h"

namespace penumbra::tune {

namespace {

ProgressEvent reference_event(const std::string& system) {
  ProgressEvent e;
  e.system = system;
  e.reference = true;
  return e;
}

template <class Tuner>
auto search(const std::string& name, const Tuner& tuner, double budget,
            const TuneProgress& progress) {
  const auto& knobs = tuner.knobs();
  int grid = 1;
  for (const Knob& k : knobs) grid *= static_cast<int>(k.values.size());
  ProgressEvent last;
  const SearchResult r = greedy_search(
      knobs, budget,
      [&](const Config& c) {
        const Evaluation e = tuner.evaluate(tuner.tuning(c));
        if (progress) {
          ProgressEvent ev;
          ev.system = name;
          ev.grid = grid;
          ev.config = describe(knobs, c);
          ev.eval = e;
          ev.evaluations = -1;  // filled in by the callback below
          last = ev;
        }
        return e;
      },
      [&](int n) {
        if (!progress) return;
        last.evaluations = n;
        progress(last);
      });
  auto t = tuner.tuning(r.best);
  t.result.tuned = true;
  t.result.error = r.best_eval.error;
  t.result.met = r.met;
  t.result.cost = r.best_eval.cost;
  t.result.ms = r.best_eval.ms;
  t.result.evaluations = r.evaluations;
  t.result.grid = r.grid;
  return t;
}

template <class T>
void remeasure(T& t, const Evaluation& e, double budget) {
  t.result.error = e.error;
  t.result.ms = e.ms;
  t.result.cost = e.cost;
  t.result.met = e.error <= budget;
}

}  // namespace

settings::TunedSettings run_tune(const TuneScene& scene, double budget, const TuneOptions& options,
                                 const TuneProgress& progress) {
  settings::TunedSettings s;
  s.scene = scene.name;
  s.budget = budget;
  {
    if (progress) progress(reference_event("terrain"));
    const TerrainTuner tuner(scene, options);
    s.terrain = search("terrain", tuner, budget, progress);
  }
  {
    if (progress) progress(reference_event("blockers"));
    const BlockerTuner tuner(scene, options);
    s.blockers = search("blockers", tuner, budget, progress);
  }
  {
    if (progress) progress(reference_event("spherical_lights"));
    const SphericalLightTuner tuner(scene, options);
    s.spherical_lights = search("spherical_lights", tuner, budget, progress);
  }
  {
    if (progress) progress(reference_event("probes"));
    const ProbeTuner tuner(scene, options);
    s.probes = search("probes", tuner, budget, progress);
  }
  return s;
}

settings::TunedSettings evaluate_settings(const TuneScene& scene, const settings::TunedSettings& in,
                                          const TuneOptions& options) {
  settings::TunedSettings s = in;
  if (s.terrain.result.tuned)
    remeasure(s.terrain, TerrainTuner(scene, options).evaluate(s.terrain), s.budget);
  if (s.blockers.result.tuned)
    remeasure(s.blockers, BlockerTuner(scene, options).evaluate(s.blockers), s.budget);
  if (s.spherical_lights.result.tuned)
    remeasure(s.spherical_lights, SphericalLightTuner(scene, options).evaluate(s.spherical_lights),
              s.budget);
  if (s.probes.result.tuned)
    remeasure(s.probes, ProbeTuner(scene, options).evaluate(s.probes), s.budget);
  return s;
}

}  // namespace penumbra::tune
