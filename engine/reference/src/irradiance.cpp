// Environment irradiance: stratified multiple importance sampling (Veach 1997, sec. 9.2,
// multi-sample model with equal counts) of cosine-weighted directions and the map's
// piecewise-constant luminance distribution.
#include <array>
#include <limits>
#include <numbers>
#include <vector>

#include "common.h"
#include "penumbra/reference/sampling.h"

namespace penumbra::reference {
namespace {

using detail::kInf;

using detail::mis_weight;

// A sampled direction that may contribute `value` (radiance x MIS weight x cos / pdf) to the
// half-pair `slot` (2 h + k) if its shadow ray escapes. Cosine samples first record only their
// texel (value filled in by a second pass).
struct Candidate {
  glm::vec3 dir;
  glm::vec3 value;
  int slot;
  std::uint32_t texel;  // cosine samples: environment texel index; else kNoTexel
};
constexpr std::uint32_t kNoTexel = ~0u;

// Per receiver: (1) draw every sample, (2) read the cosine samples' texels in a tight loop of
// independent loads (their cache misses overlap), (3) cast the shadow rays, (4) pair up.
RgbEstimate irradiance_estimate(const Scene& scene, const EnvironmentSampler& env,
                                const Receiver& r, std::size_t index, const IrradianceOptions& o) {
  const detail::Shading s = detail::shading(scene, r, o.ray_offset);
  const Frame frame(s.n);
  const bool use_cos = o.strategy != EnvironmentStrategy::kEnvironment;
  const bool use_env = o.strategy != EnvironmentStrategy::kCosine && env.can_sample();
  RgbEstimate out;
  if (!use_cos && !use_env) return out;  // environment-only sampling of a black map: exactly 0
  const int strategies = int(use_cos) + int(use_env);
  const StrataGrid grid = StrataGrid::for_count(o.samples / (2 * strategies), o.stratified);
  Pcg32 rng(o.seed, index, detail::kEnvironmentSalt);

  thread_local std::vector<Candidate> candidates;
  thread_local std::vector<std::array<double, 3>> halves;
  candidates.clear();
  halves.assign(2 * static_cast<std::size_t>(grid.count()), std::array<double, 3>{});
  for (int slot = 0; slot < 2 * grid.count(); ++slot) {
    const int h = slot / 2;
    if (use_cos) {
      const glm::vec3 local = cosine_hemisphere(to_float(grid.point(h, rng)));
      if (local.z > 0) {
        const glm::vec3 dir = frame.to_world(local);
        candidates.push_back(
            {dir, glm::vec3(local.z), slot, static_cast<std::uint32_t>(env.texel_index(dir))});
      }
    }
    if (use_env) {
      const EnvironmentSampler::Sample e = env.sample(grid.point(h, rng));
      const double cos = glm::dot(s.n, e.dir);
      if (cos > 0) {
        const double w = use_cos ? mis_weight(o.heuristic, e.pdf, cos * std::numbers::inv_pi) : 1.0;
        candidates.push_back(
            {e.dir, e.radiance * static_cast<float>(w * cos / e.pdf), slot, kNoTexel});
      }
    }
  }
  for (Candidate& c : candidates) {
    if (c.texel == kNoTexel) continue;
    const EnvironmentSampler::Lookup l = env.texel(c.texel);
    const double p_cos = c.value.x * std::numbers::inv_pi;  // value holds cos(theta) here
    const double w = use_env ? mis_weight(o.heuristic, p_cos, l.pdf) : 1.0;
    c.value = l.radiance * static_cast<float>(w * std::numbers::pi);  // cos / p_cos = pi
  }
  std::uint32_t rays = 0;
  for (const Candidate& c : candidates) {
    if (!(luminance(c.value) > 0)) continue;  // black texel or zero weight: no ray needed
    ++rays;
    if (scene.occluded(s.origin, c.dir, kInf)) continue;
    for (int k = 0; k < 3; ++k) halves[c.slot][k] += c.value[k];
  }
  PairedMean<3> acc;
  for (int h = 0; h < grid.count(); ++h) acc.add_pair(halves[2 * h], halves[2 * h + 1]);

  const glm::vec3 scale = o.albedo ? *o.albedo * std::numbers::inv_pi_v<float> : glm::vec3(1.0f);
  for (int c = 0; c < 3; ++c) {
    out.mean[c] = static_cast<float>(acc.mean(c) * scale[c]);
    out.std_error[c] = static_cast<float>(acc.std_error(c) * scale[c]);
  }
  out.samples = static_cast<std::uint32_t>(2 * strategies * grid.count());
  out.rays = rays;
  out.dof = static_cast<std::uint32_t>(acc.dof());
  return out;
}

}  // namespace

std::vector<RgbEstimate> environment_irradiance(const Scene& scene,
                                                std::span<const Receiver> receivers,
                                                const IrradianceOptions& options) {
  constexpr const char* kFn = "reference::environment_irradiance";
  detail::check_options(options, kFn);
  detail::check_albedo(options.albedo, kFn);
  detail::check_receivers(receivers, false, kFn);
  std::vector<RgbEstimate> out(receivers.size());
  const EnvironmentSampler* env = scene.environment();
  if (env == nullptr) return out;
  detail::for_each_receiver(receivers.size(), [&](std::size_t i) {
    out[i] = irradiance_estimate(scene, *env, receivers[i], i, options);
  });
  return out;
}

}  // namespace penumbra::reference
