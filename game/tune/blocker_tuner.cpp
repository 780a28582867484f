#include "blocker_tuner.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>

#include "object_receivers.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "sky_split.h"

namespace penumbra::tune {

namespace ba = blocker_accumulation;

namespace {

template <int N>
Evaluation run_blockers(const TuneScene& s, const SplitSky& sky,
                        const std::vector<data::Sphere>& spheres, const settings::BlockerTuning& t,
                        const TuneOptions& o, const std::vector<glm::vec3>& points,
                        const std::vector<glm::vec3>& ref) {
  const sh::CoeffsRgb<N> radiance = environment_sh<N>(sky.rest, s.rotation_rad());
  ba::BlockerSettings settings;
  settings.blocker.epsilon = t.epsilon;
  ba::BlockerAccumulation<N> method(settings);
  std::vector<ba::WorldSphere> world;
  for (const data::Sphere& sp : spheres) world.push_back({sp.centre, sp.radius});
  method.set_blockers(std::move(world));
  std::vector<glm::vec3> e(points.size());
  Evaluation out;
  out.ms = min_ms(o.timing_reps, [&] {
    const glm::vec3 n(0, 0, 1);
    for (std::size_t i = 0; i < points.size(); ++i) {
      e[i] = method.irradiance(radiance, points[i], n);
      // Key lights as blockers.shade adds them: the disc occluded by the blockers.
      for (const KeyLight& k : sky.keys)
        e[i] += k.irradiance * std::max(0.0f, glm::dot(n, k.direction)) *
                method.key_light_visibility(points[i], k.direction, k.angular_radius);
    }
  });
  out.cost = out.ms;
  out.error = rel_rms(e, ref);
  return out;
}

}  // namespace

BlockerTuner::BlockerTuner(const TuneScene& scene, const TuneOptions& options)
    : scene_(scene),
      options_(options),
      sky_(split_sky(scene.environment, scene.rotation_rad(), options.key_lights)) {
  knobs_ = {{"spheres", {"4", "8", "16", "32", "64"}},
            {"epsilon", {"0.4", "0.3", "0.2", "0.1"}},
            {"bands", {"3", "4", "5", "6"}}};
  if (scene.objects.empty())
    throw std::runtime_error(scene.source + ": blockers: the scene has no objects");
  points_ = ground_receivers(scene);
  std::vector<reference::Receiver> receivers;
  for (const glm::vec3& p : points_) receivers.push_back({p, glm::vec3(0, 0, 1)});
  const reference::SceneDesc d = object_scene(scene);
  const reference::Scene traced(d);
  reference::IrradianceOptions io;
  io.samples = options.reference_samples;
  io.seed = options.seed;
  for (const reference::RgbEstimate& r : reference::environment_irradiance(traced, receivers, io))
    reference_.push_back(r.mean);
}

const std::vector<data::Sphere>& BlockerTuner::world_spheres(int count) const {
  auto it = fits_.find(count);
  if (it != fits_.end()) return it->second;
  std::vector<data::Sphere> out;
  for (const TuneObject& o : scene_.objects) {
    const std::vector<data::Sphere> fit = fit_world_spheres(o, count, options_.seed);
    out.insert(out.end(), fit.begin(), fit.end());
  }
  return fits_.emplace(count, std::move(out)).first->second;
}

settings::BlockerTuning BlockerTuner::tuning(const Config& c) const {
  settings::BlockerTuning t;
  t.spheres_per_object = std::stoi(knobs_[0].values[static_cast<std::size_t>(c[0])]);
  t.epsilon = std::stof(knobs_[1].values[static_cast<std::size_t>(c[1])]);
  t.bands = std::stoi(knobs_[2].values[static_cast<std::size_t>(c[2])]);
  return t;
}

Evaluation BlockerTuner::evaluate(const settings::BlockerTuning& t) const {
  const std::vector<data::Sphere>& spheres = world_spheres(t.spheres_per_object);
  switch (t.bands) {
    case 3:
      return run_blockers<3>(scene_, sky_, spheres, t, options_, points_, reference_);
    case 4:
      return run_blockers<4>(scene_, sky_, spheres, t, options_, points_, reference_);
    case 5:
      return run_blockers<5>(scene_, sky_, spheres, t, options_, points_, reference_);
    case 6:
      return run_blockers<6>(scene_, sky_, spheres, t, options_, points_, reference_);
    default:
      throw std::invalid_argument("blockers: bands must be 3..6, got " + std::to_string(t.bands));
  }
}

}  // namespace penumbra::tune
