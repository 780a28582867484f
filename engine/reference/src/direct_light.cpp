#include "direct_light.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/ext/vector_double3.hpp>

#include "common.h"
#include "penumbra/reference/sampling.h"

namespace penumbra::reference::detail {
namespace {
using detail::black;
using detail::kInf;
}  // namespace

// Unbiased estimate of the direct irradiance (environment + lights) at x, unit normal n, with
// o.samples directions per source; counts the shadow rays it casts.
glm::dvec3 direct_irradiance(const Scene& scene, const glm::vec3& x, const glm::vec3& n,
                             const DirectOptions& o, Pcg32& rng, std::uint32_t& rays) {
  const detail::Shading s = detail::shading(scene, Receiver{x, n}, o.ray_offset);
  glm::dvec3 total(0.0);
  const EnvironmentSampler* env = scene.environment();
  if (env != nullptr && env->can_sample()) {
    // Multi-sample MIS with equal counts: one cosine and one map sample per stratum.
    const StrataGrid grid = StrataGrid::for_count(std::max(1, o.samples / 2), true);
    const Frame frame(s.n);
    glm::dvec3 sum(0.0);
    for (int h = 0; h < grid.count(); ++h) {
      const glm::vec3 local = cosine_hemisphere(to_float(grid.point(h, rng)));
      if (local.z > 0) {
        const glm::vec3 dir = frame.to_world(local);
        const EnvironmentSampler::Lookup l = env->lookup(dir);
        const double w = detail::mis_weight(o.heuristic, local.z * std::numbers::inv_pi, l.pdf);
        const glm::dvec3 value = glm::dvec3(l.radiance) * (w * std::numbers::pi);
        if (luminance(l.radiance) > 0) {
          ++rays;
          if (!scene.occluded(s.origin, dir, kInf)) sum += value;
        }
      }
      const EnvironmentSampler::Sample e = env->sample(grid.point(h, rng));
      const double cos = glm::dot(s.n, e.dir);
      if (cos > 0) {
        const double w = detail::mis_weight(o.heuristic, e.pdf, cos * std::numbers::inv_pi);
        ++rays;
        if (!scene.occluded(s.origin, e.dir, kInf))
          sum += glm::dvec3(e.radiance) * (w * cos / e.pdf);
      }
    }
    total += sum / double(grid.count());
  }
  // Lights: uniform in each cone seen from x itself, shadow rays to the near surface.
  const StrataGrid grid = StrataGrid::for_count(o.samples, true);
  const glm::dvec3 p(x), origin(s.origin);
  for (const SphereLight& light : scene.lights()) {
    if (black(light.radiance)) continue;
    const glm::dvec3 d = glm::dvec3(light.center) - p;
    const double dist2 = glm::dot(d, d), r2 = double(light.radius) * light.radius;
    if (dist2 <= r2) continue;  // x inside or on the light: culled (scene.h)
    const double dist = std::sqrt(dist2), sin2 = r2 / dist2, cos_max = std::sqrt(1 - sin2);
    const glm::dvec3 axis = d / dist;
    if (glm::dot(axis, glm::dvec3(s.n)) <= -std::sqrt(sin2)) continue;  // below the horizon
    const double one_minus_cos = sin2 / (1 + cos_max);
    const Frame frame{glm::vec3(axis)};
    const glm::dvec3 center(light.center);
    double sum = 0;
    for (int h = 0; h < grid.count(); ++h) {
      const glm::vec3 dir =
          frame.to_world(uniform_cone(to_float(grid.point(h, rng)), one_minus_cos));
      const double cos = glm::dot(s.n, dir);
      if (cos <= 0) continue;
      const glm::dvec3 c = center - origin, w(dir);
      const glm::dvec3 perp = glm::cross(c, w);
      const double t = glm::dot(c, w) - std::sqrt(std::fmax(0.0, r2 - glm::dot(perp, perp)));
      ++rays;
      if (scene.occluded(s.origin, dir, static_cast<float>(t))) continue;
      sum += cos * 2 * std::numbers::pi * one_minus_cos;  // cos / pdf
    }
    total += glm::dvec3(light.radiance) * (sum / grid.count());
  }
  return total;
}

}  // namespace penumbra::reference::detail
