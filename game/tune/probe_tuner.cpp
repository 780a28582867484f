#include "probe_tuner.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/probe_bake/bake_scene.h"
#include "penumbra/systems/probe_bake/probe_bake.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

namespace penumbra::tune {

namespace {

const std::array<glm::vec3, 6> kNormals = {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0),
                                           glm::vec3(0, 1, 0), glm::vec3(0, -1, 0),
                                           glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)};
constexpr float kClear = 0.5f;  // test points at least this far from every solid along the axes

}  // namespace

ProbeTuner::ProbeTuner(const TuneScene& scene, const TuneOptions& options)
    : scene_(scene), options_(options) {
  knobs_ = {{"probes_per_side", {"3", "4", "6", "8", "11", "16", "22"}},
            {"placement", {"grid", "spawn_merge"}}};
  const probe_bake::BakeScene bake = probe_bake::parse_bake_scene(
      bake_scene_json(scene, side() / 2), scene.source, scene.data_dir);
  traced_ = std::make_unique<reference::Scene>(bake.desc);
  // Free test points: uniform in the probe volume, clear of every solid (terrain included).
  std::mt19937 rng(static_cast<std::uint32_t>(options.seed) + 5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int tries = 0;
  while (static_cast<int>(points_.size()) < scene.probe_points) {
    if (++tries > 1000 * scene.probe_points)
      throw std::runtime_error(scene.source + ": probes: too few free points in the probe volume");
    // z, y, x: one order for every compiler (in glm::vec3(u(rng), u(rng), u(rng)) it is the
    // compiler's), GCC's, which set the tuning's recorded results.
    const float pz = u(rng), py = u(rng), px = u(rng);
    const glm::vec3 p =
        scene.probe_min + (scene.probe_max - scene.probe_min) * glm::vec3(px, py, pz);
    bool clear = !bake.inside(p);
    for (float d : {kClear, -kClear})
      for (int k = 0; k < 3; ++k) {
        glm::vec3 q = p;
        q[k] += d;
        clear = clear && !bake.inside(q);
      }
    if (clear) points_.push_back(p);
  }
  std::vector<reference::Receiver> rec;
  for (const glm::vec3& p : points_)
    for (const glm::vec3& n : kNormals) rec.push_back({p, n});
  reference::IrradianceOptions eo;
  eo.samples = options.reference_samples;
  eo.seed = options.seed;
  reference::BounceOptions bo;
  bo.samples = options.bounce_samples;
  bo.seed = options.seed + 1;
  const auto env = reference::environment_irradiance(*traced_, rec, eo);
  const auto bounce = reference::indirect_irradiance(*traced_, rec, bo);
  for (std::size_t i = 0; i < rec.size(); ++i)
    reference_.push_back(reference::combine(env[i], bounce[i]).mean);
}

ProbeTuner::~ProbeTuner() = default;

float ProbeTuner::side() const {
  return std::max(scene_.probe_max.x - scene_.probe_min.x, scene_.probe_max.y - scene_.probe_min.y);
}

settings::ProbeTuning ProbeTuner::tuning(const Config& c) const {
  settings::ProbeTuning t;
  t.probes_per_side = std::stoi(knobs_[0].values[static_cast<std::size_t>(c[0])]);
  t.spacing = side() / static_cast<float>(t.probes_per_side - 1);
  t.placement = knobs_[1].values[static_cast<std::size_t>(c[1])];
  return t;
}

Evaluation ProbeTuner::evaluate(const settings::ProbeTuning& t) const {
  const float spacing = side() / static_cast<float>(t.probes_per_side - 1);
  const probe_bake::BakeScene bake = probe_bake::parse_bake_scene(bake_scene_json(scene_, spacing),
                                                                  scene_.source, scene_.data_dir);
  probe_bake::BakeSettings bs;
  bs.samples = options_.probe_capture_samples;
  bs.seed = options_.seed + 2;
  bs.spacing = spacing;
  bs.placement = t.placement == "spawn_merge" ? probe_bake::PlacementMethod::kSpawnMerge
                 : t.placement == "gradient"  ? probe_bake::PlacementMethod::kGradient
                                              : probe_bake::PlacementMethod::kGrid;
  const auto t0 = std::chrono::steady_clock::now();
  const data::ProbeCloud cloud = probe_bake::bake_probe_cloud(bake, *traced_, bs);
  const auto t1 = std::chrono::steady_clock::now();
  Evaluation out;
  out.ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  out.cost = static_cast<double>(cloud.probe_count());
  const probe_cloud::ProbeTetWalk walk(std::make_shared<const data::ProbeCloud>(cloud));
  std::vector<glm::vec3> e;
  for (const glm::vec3& p : points_) {
    const probe_cloud::ProbeSh sh_e = walk.interpolate(walk.locate(p, -1));
    for (const glm::vec3& n : kNormals) {
      const auto y = sh::eval_basis<probe_cloud::kProbeShBands>(n);
      glm::vec3 v(0.0f);
      for (int c = 0; c < 3; ++c)
        for (std::size_t j = 0; j < y.size(); ++j) v[c] += sh_e[c][j] * y[j];
      e.push_back(v);
    }
  }
  out.error = rel_rms(e, reference_);
  return out;
}

}  // namespace penumbra::tune
