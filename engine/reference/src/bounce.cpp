// One diffuse bounce: stratified cosine-weighted first-hit directions at the receiver; at each
// hit of a reflective occluder an unbiased estimate of its direct irradiance (environment by
// MIS as in irradiance.cpp, each spherical light by cone sampling as in lights.cpp), times the
// albedo. With cosine sampling, L_1 cos / pdf = pi * albedo / pi * E_direct = albedo E_direct
// (PBRT 3rd ed. sec. 14.5, a path of length 2 with next-event estimation at its vertex).
// Ground truth for the diffuse reflection off dynamic objects of [Guerrero08]; docs/reference.md,
// "One diffuse bounce", gives the variance and the cost.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/ext/vector_double3.hpp>

#include "common.h"
#include "direct_light.h"
#include "penumbra/reference/sampling.h"

namespace penumbra::reference {
namespace {

using detail::kInf;

using detail::black;

RgbEstimate bounce_estimate(const Scene& scene, const Receiver& r, std::size_t index,
                            const BounceOptions& o) {
  const detail::Shading s = detail::shading(scene, r, o.ray_offset);
  const Frame frame(s.n);
  const StrataGrid grid = StrataGrid::for_count(o.samples / 2, o.stratified);
  Pcg32 rng(o.seed, index, detail::kBounceSalt);
  PairedMean<3> acc;
  std::uint32_t rays = 0;
  for (int h = 0; h < grid.count(); ++h) {
    std::array<double, 3> g[2] = {};
    for (auto& gk : g) {
      const glm::vec3 local = cosine_hemisphere(to_float(grid.point(h, rng)));
      if (!(local.z > 0)) continue;  // measure zero
      const glm::vec3 dir = frame.to_world(local);
      ++rays;
      const Hit hit = scene.first_hit(s.origin, dir, kInf);
      if (!hit || black(hit.albedo)) continue;  // escaped (the direct term) or reflects nothing
      const glm::dvec3 e =
          detail::direct_irradiance(scene, s.origin + hit.distance * dir, hit.normal,
                                    {o.bounce_samples, o.heuristic, o.ray_offset}, rng, rays);
      for (int k = 0; k < 3; ++k) gk[k] = hit.albedo[k] * e[k];  // pi L_1 = albedo E_direct
    }
    acc.add_pair(g[0], g[1]);
  }
  RgbEstimate out;
  for (int k = 0; k < 3; ++k) {
    out.mean[k] = static_cast<float>(acc.mean(k));
    out.std_error[k] = static_cast<float>(acc.std_error(k));
  }
  out.samples = static_cast<std::uint32_t>(2 * grid.count());
  out.rays = rays;
  out.dof = static_cast<std::uint32_t>(acc.dof());
  return out;
}

}  // namespace

std::vector<RgbEstimate> indirect_irradiance(const Scene& scene,
                                             std::span<const Receiver> receivers,
                                             const BounceOptions& options) {
  constexpr const char* kFn = "reference::indirect_irradiance";
  detail::check_options(options, kFn);
  if (options.bounce_samples < 1) {
    throw std::invalid_argument(std::string(kFn) + ": bounce_samples = " +
                                std::to_string(options.bounce_samples) + " must be >= 1");
  }
  detail::check_receivers(receivers, false, kFn);
  std::vector<RgbEstimate> out(receivers.size());
  const EnvironmentSampler* env = scene.environment();
  bool emits = env != nullptr && env->can_sample();
  for (const SphereLight& l : scene.lights()) emits = emits || !black(l.radiance);
  if (!scene.reflects() || !emits) {
    const auto samples = static_cast<std::uint32_t>(
        2 * StrataGrid::for_count(options.samples / 2, options.stratified).count());
    for (RgbEstimate& e : out) e.samples = samples;
    return out;
  }
  detail::for_each_receiver(receivers.size(), [&](std::size_t i) {
    out[i] = bounce_estimate(scene, receivers[i], i, options);
  });
  return out;
}

}  // namespace penumbra::reference
