// Irradiance from spherical lights: stratified uniform sampling of the cone each light subtends
// (PBRT 3rd ed. sec. 14.2.2), shadow rays ending at the light's near surface.
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/ext/vector_double3.hpp>

#include "common.h"
#include "penumbra/reference/sampling.h"

namespace penumbra::reference {
namespace {

struct Cone {
  glm::dvec3 center;
  double radius2;
  double one_minus_cos;  // 1 - cos(angular radius), without cancellation
  Frame frame;
  glm::vec3 radiance;
};

RgbEstimate light_estimate(const Scene& scene, const Receiver& r, std::size_t index,
                           const LightOptions& o) {
  // The cones are those seen from the receiver itself; only the shadow rays start at the
  // offset origin (so the offset biases nothing but visibility).
  const detail::Shading s = detail::shading(scene, r, o.ray_offset);
  const glm::dvec3 p(r.position), origin(s.origin);
  std::vector<Cone> cones;
  for (const SphereLight& light : scene.lights()) {
    const glm::dvec3 d = glm::dvec3(light.center) - p;
    const double dist2 = glm::dot(d, d), r2 = double(light.radius) * light.radius;
    if (dist2 <= r2) continue;  // receiver inside or on the light: culled (scene.h)
    const double dist = std::sqrt(dist2), sin2 = r2 / dist2, cos_max = std::sqrt(1 - sin2);
    const glm::dvec3 axis = d / dist;
    // Entirely below the horizon (angle to n >= pi/2 + angular radius): contributes 0.
    if (glm::dot(axis, glm::dvec3(s.n)) <= -std::sqrt(sin2)) continue;
    const bool black = light.radiance.x <= 0 && light.radiance.y <= 0 && light.radiance.z <= 0;
    if (black) continue;
    cones.push_back({glm::dvec3(light.center), r2, sin2 / (1 + cos_max), Frame(glm::vec3(axis)),
                     light.radiance});
  }
  const StrataGrid grid = StrataGrid::for_count(o.samples / 2, o.stratified);
  RgbEstimate out;
  out.samples = static_cast<std::uint32_t>(2 * grid.count() * scene.lights().size());
  if (cones.empty()) return out;
  Pcg32 rng(o.seed, index, detail::kLightSalt);
  PairedMean<3> acc;
  std::uint32_t rays = 0;
  for (int h = 0; h < grid.count(); ++h) {
    std::array<double, 3> g[2] = {};
    for (auto& gk : g) {
      for (const Cone& c : cones) {
        const glm::vec3 dir =
            c.frame.to_world(uniform_cone(to_float(grid.point(h, rng)), c.one_minus_cos));
        const double cos = glm::dot(s.n, dir);
        if (cos <= 0) continue;
        // Near intersection with the light: t = b - sqrt(r^2 - |d x w|^2), d = center - origin.
        const glm::dvec3 d = c.center - origin, w(dir);
        const glm::dvec3 perp = glm::cross(d, w);
        const double t =
            glm::dot(d, w) - std::sqrt(std::fmax(0.0, c.radius2 - glm::dot(perp, perp)));
        ++rays;
        if (scene.occluded(s.origin, dir, static_cast<float>(t))) continue;
        const double f = cos * 2 * std::numbers::pi * c.one_minus_cos;  // cos / pdf
        for (int k = 0; k < 3; ++k) gk[k] += c.radiance[k] * f;
      }
    }
    acc.add_pair(g[0], g[1]);
  }
  const glm::vec3 scale = o.albedo ? *o.albedo * std::numbers::inv_pi_v<float> : glm::vec3(1.0f);
  for (int k = 0; k < 3; ++k) {
    out.mean[k] = static_cast<float>(acc.mean(k) * scale[k]);
    out.std_error[k] = static_cast<float>(acc.std_error(k) * scale[k]);
  }
  out.rays = rays;
  out.dof = static_cast<std::uint32_t>(acc.dof());
  return out;
}

}  // namespace

std::vector<RgbEstimate> light_irradiance(const Scene& scene, std::span<const Receiver> receivers,
                                          const LightOptions& options) {
  constexpr const char* kFn = "reference::light_irradiance";
  detail::check_options(options, kFn);
  detail::check_albedo(options.albedo, kFn);
  detail::check_receivers(receivers, false, kFn);
  std::vector<RgbEstimate> out(receivers.size());
  if (scene.lights().empty()) return out;
  detail::for_each_receiver(receivers.size(), [&](std::size_t i) {
    out[i] = light_estimate(scene, receivers[i], i, options);
  });
  return out;
}

}  // namespace penumbra::reference
