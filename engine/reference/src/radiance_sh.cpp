// Radiance SH capture at a point (radiance_sh.h): stratified uniform sphere directions with
// first hits (bounce term, MIS-weighted environment), map samples (MIS) and light cones, every
// set of samples projected onto the SH basis at once.
#include "penumbra/reference/radiance_sh.h"

#include <algorithm>
#include <array>
#include <cmath>
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
constexpr std::uint64_t kRadianceShSalt = 5;  // after common.h's four

using detail::black;

template <int N>
using Acc = std::array<double, static_cast<std::size_t>(3 * N * N)>;

// acc += radiance * y(dir) * weight
template <int N>
void project(Acc<N>& acc, const glm::dvec3& radiance, const glm::vec3& dir, double weight) {
  const sh::Coeffs<N> y = sh::eval_basis<N>(dir);
  for (int c = 0; c < 3; ++c) {
    const double v = radiance[c] * weight;
    if (v == 0) continue;
    for (int i = 0; i < N * N; ++i) acc[static_cast<std::size_t>(c * N * N + i)] += v * y[i];
  }
}

template <int N>
RadianceShEstimate<N> radiance_estimate(const Scene& scene, const glm::vec3& p, std::size_t index,
                               const RadianceShOptions& o) {
  const StrataGrid grid = StrataGrid::for_count(o.samples / 2, o.stratified);
  Pcg32 rng(o.seed, index, kRadianceShSalt);
  const EnvironmentSampler* env = scene.environment();
  const bool direct = o.direct;
  const bool sample_env = direct && env != nullptr && env->can_sample();
  constexpr double kSpherePdf = 0.25 * std::numbers::inv_pi;
  const bool bounce = o.bounce && scene.reflects();
  PairedMean<static_cast<std::size_t>(3 * N * N)> acc;
  RadianceShEstimate<N> out;
  std::uint32_t rays = 0;
  for (int h = 0; h < grid.count(); ++h) {
    Acc<N> g[2] = {};
    for (Acc<N>& gk : g) {
      // Uniform sphere direction: bounce or (MIS-weighted) environment.
      const glm::vec3 dir = uniform_sphere(to_float(grid.point(h, rng)));
      ++rays;
      const Hit hit = scene.first_hit(p, dir, kInf);
      if (hit) {
        ++out.hits;
        if (o.back_face && o.back_face(p, dir, hit)) {
          ++out.back_face_hits;
          if (hit.distance < out.escape_distance) {
            out.escape_distance = hit.distance;
            out.escape_dir = dir;
          }
        } else if (bounce && !black(hit.albedo)) {
          const glm::dvec3 e =
              detail::direct_irradiance(scene, p + hit.distance * dir, hit.normal,
                                        {o.bounce_samples, o.heuristic, o.ray_offset}, rng, rays);
          project<N>(gk, glm::dvec3(hit.albedo) * e * std::numbers::inv_pi, dir, 1 / kSpherePdf);
        }
      } else if (direct && env != nullptr) {
        const EnvironmentSampler::Lookup l = env->lookup(dir);
        const double w = sample_env ? detail::mis_weight(o.heuristic, kSpherePdf, l.pdf) : 1.0;
        project<N>(gk, glm::dvec3(l.radiance), dir, w / kSpherePdf);
      }
      // Environment map direction (MIS).
      if (sample_env) {
        const EnvironmentSampler::Sample e = env->sample(grid.point(h, rng));
        const double w = detail::mis_weight(o.heuristic, e.pdf, kSpherePdf);
        ++rays;
        if (!scene.occluded(p, e.dir, kInf))
          project<N>(gk, glm::dvec3(e.radiance), e.dir, w / e.pdf);
      }
      // One cone direction per light.
      for (const SphereLight& light : scene.lights()) {
        if (!direct || black(light.radiance)) continue;
        const glm::dvec3 d = glm::dvec3(light.center) - glm::dvec3(p);
        const double dist2 = glm::dot(d, d), r2 = double(light.radius) * light.radius;
        if (dist2 <= r2) continue;  // inside or on the light: culled (scene.h)
        const double dist = std::sqrt(dist2), sin2 = r2 / dist2, cos_max = std::sqrt(1 - sin2);
        const double one_minus_cos = sin2 / (1 + cos_max);
        const Frame frame{glm::vec3(d / dist)};
        const glm::vec3 ldir =
            frame.to_world(uniform_cone(to_float(grid.point(h, rng)), one_minus_cos));
        const glm::dvec3 w(ldir);
        const glm::dvec3 perp = glm::cross(d, w);
        const double t = glm::dot(d, w) - std::sqrt(std::fmax(0.0, r2 - glm::dot(perp, perp)));
        ++rays;
        if (scene.occluded(p, ldir, static_cast<float>(t))) continue;
        project<N>(gk, glm::dvec3(light.radiance), ldir, 2 * std::numbers::pi * one_minus_cos);
      }
    }
    acc.add_pair(g[0], g[1]);
  }
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < N * N; ++i) {
      const auto k = static_cast<std::size_t>(c * N * N + i);
      out.mean[c][i] = static_cast<float>(acc.mean(k));
      out.std_error[c][i] = static_cast<float>(acc.std_error(k));
    }
  out.samples = static_cast<std::uint32_t>(2 * grid.count());
  out.rays = rays;
  out.dof = static_cast<std::uint32_t>(acc.dof());
  return out;
}

}  // namespace

template <int N>
std::vector<RadianceShEstimate<N>> radiance_sh(const Scene& scene,
                                               std::span<const glm::vec3> points,
                                               const RadianceShOptions& options) {
  static_assert(N >= 2 && N <= 4);
  constexpr const char* kFn = "reference::radiance_sh";
  detail::check_options(options, kFn);
  if (options.samples < 2)
    throw std::invalid_argument(std::string(kFn) +
                                ": samples = " + std::to_string(options.samples) + " must be >= 2");
  if (options.bounce_samples < 1)
    throw std::invalid_argument(std::string(kFn) + ": bounce_samples = " +
                                std::to_string(options.bounce_samples) + " must be >= 1");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!detail::finite(points[i]))
      throw std::invalid_argument(std::string(kFn) + ": points[" + std::to_string(i) +
                                  "] is not finite");
  std::vector<RadianceShEstimate<N>> out(points.size());
  detail::for_each_receiver(points.size(), [&](std::size_t i) {
    out[i] = radiance_estimate<N>(scene, points[i], options.first_index + i, options);
  });
  return out;
}

template std::vector<RadianceShEstimate<2>> radiance_sh<2>(const Scene&, std::span<const glm::vec3>,
                                                           const RadianceShOptions&);
template std::vector<RadianceShEstimate<3>> radiance_sh<3>(const Scene&, std::span<const glm::vec3>,
                                                           const RadianceShOptions&);
template std::vector<RadianceShEstimate<4>> radiance_sh<4>(const Scene&, std::span<const glm::vec3>,
                                                           const RadianceShOptions&);

}  // namespace penumbra::reference
