#include "spherical_light_tuner.h"

#include <span>
#include <stdexcept>
#include <string>

#include <tbb/task_arena.h>

#include "object_receivers.h"
#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/spherical_lights/reflector_lighting.h"
#include "penumbra/systems/spherical_lights/reflector_samples.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"

namespace penumbra::tune {

namespace ba = blocker_accumulation;
namespace sl = spherical_lights;

namespace {

constexpr int N = 4;          // the system's bands (spherical_lights::kSystemBands)
constexpr int kSpheres = 16;  // per object: the main job's boulders (BoulderConfig::spheres)

}  // namespace

SphericalLightTuner::SphericalLightTuner(const TuneScene& scene, const TuneOptions& options)
    : scene_(scene), options_(options) {
  knobs_ = {{"directions_frequency", {"1", "2", "3", "4"}},
            {"blocking", {"per_object", "per_sphere"}},
            {"horizon", {"shrink", "clip"}},
            {"gather", {"clusters_parents", "clusters_leaves", "receivers"}}};
  if (scene.objects.empty())
    throw std::runtime_error(scene.source + ": spherical lights: the scene has no objects");
  points_ = ground_receivers(scene);
  std::vector<reference::Receiver> receivers;
  for (const glm::vec3& p : points_) receivers.push_back({p, glm::vec3(0, 0, 1)});
  for (const TuneObject& o : scene.objects)
    spheres_.push_back(fit_world_spheres(o, kSpheres, options.seed));
  {
    const std::vector<glm::vec3> up(points_.size(), glm::vec3(0, 0, 1));
    sl::SlClusterSettings cs;  // the default far_ratio
    cs.hierarchy = sl::SlHierarchy::kLeaves;
    leaves_ = sl::cluster_receivers(points_, up, cs);
    cs.hierarchy = sl::SlHierarchy::kParents;
    parents_ = sl::cluster_receivers(points_, up, cs);
  }
  const reference::SceneDesc d = object_scene(scene);
  const reference::Scene traced(d);
  reference::BounceOptions bo;
  bo.samples = 4 * options.bounce_samples;
  bo.bounce_samples = 8;
  bo.seed = options.seed + 3;
  for (const reference::RgbEstimate& r : reference::indirect_irradiance(traced, receivers, bo))
    reference_.push_back(r.mean);
}

const std::vector<data::ReflectorSamples>& SphericalLightTuner::samples(int frequency) const {
  auto it = samples_.find(frequency);
  if (it != samples_.end()) return it->second;
  std::vector<data::ReflectorSamples> out;
  sl::ReflectorSettings rs;
  rs.geodesic_frequency = frequency;
  for (std::size_t k = 0; k < scene_.objects.size(); ++k) {
    data::MeshData mesh = scene_.objects[k].mesh;
    mesh.base_color = glm::vec4(scene_.objects[k].albedo, 1.0f);
    out.push_back(sl::sample_reflector(mesh, spheres_[k], rs, scene_.objects[k].albedo));
  }
  return samples_.emplace(frequency, std::move(out)).first->second;
}

settings::SphericalLightTuning SphericalLightTuner::tuning(const Config& c) const {
  settings::SphericalLightTuning t;
  t.directions_frequency = std::stoi(knobs_[0].values[static_cast<std::size_t>(c[0])]);
  t.blocking = knobs_[1].values[static_cast<std::size_t>(c[1])];
  t.horizon = knobs_[2].values[static_cast<std::size_t>(c[2])];
  t.gather = knobs_[3].values[static_cast<std::size_t>(c[3])];
  return t;
}

Evaluation SphericalLightTuner::evaluate(const settings::SphericalLightTuning& t) const {
  const std::vector<data::ReflectorSamples>& objects = samples(t.directions_frequency);
  const sh::CoeffsRgb<N> env = environment_sh<N>(scene_.environment, scene_.rotation_rad());
  // The blockers: every object's spheres, one group each (as blockers.gather groups a set).
  std::vector<ba::WorldSphere> spheres;
  std::vector<ba::BlockerGroup> groups;
  for (const std::vector<data::Sphere>& set : spheres_) {
    const auto first = static_cast<std::uint32_t>(spheres.size());
    for (const data::Sphere& s : set) spheres.push_back({s.centre, s.radius});
    groups.push_back(ba::bound_group(std::span(spheres).subspan(first), first));
  }
  ba::BlockerAccumulation<N> blockers;
  blockers.set_blockers(spheres, groups);
  const sl::ReflectorLighting<N> lighting(objects.front().directions);
  sl::SphereLightSettings settings;
  settings.blocking =
      t.blocking == "per_object" ? sl::SlBlocking::kPerObject : sl::SlBlocking::kPerSphere;
  settings.horizon = t.horizon == "clip" ? sl::EmitterHorizon::kClip : sl::EmitterHorizon::kShrink;
  const sl::SlReceiverClusters* clusters = t.gather == "clusters_leaves"    ? &leaves_
                                           : t.gather == "clusters_parents" ? &parents_
                                                                            : nullptr;
  tbb::task_arena one(1);  // shade(clusters) runs in the caller's arena: one thread, as below
  std::vector<glm::vec3> e(points_.size());
  Evaluation out;
  out.ms = min_ms(options_.timing_reps, [&] {
    std::vector<sl::SphereLightSource<N>> lights;
    for (std::uint32_t id = 0; id < objects.size(); ++id) {
      const auto radiance = lighting.update(objects[id], {}, blockers, env);  // pass 1
      sl::ReflectorLighting<N>::place(objects[id], {}, radiance, id, lights);
    }
    sl::SphereLightGather<N> gather(settings);  // pass 2
    gather.set_lights(std::move(lights));
    if (clusters)
      one.execute([&] { gather.shade(*clusters, e); });
    else
      for (std::size_t i = 0; i < points_.size(); ++i)
        e[i] = gather.irradiance(points_[i], glm::vec3(0, 0, 1));
  });
  out.cost = out.ms;
  out.error = rel_rms(e, reference_);
  return out;
}

}  // namespace penumbra::tune
