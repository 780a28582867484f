#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "input_checks.h"
#include "penumbra/sh/batch.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/product.h"
#include "penumbra/sh/rotation.h"
#include "penumbra/systems/blocker_accumulation/blocker_log_sum.h"

namespace penumbra::blocker_accumulation {
namespace {

using detail::finite;
using detail::str;

}  // namespace

BlockerGroup bound_group(std::span<const WorldSphere> spheres, std::uint32_t first) {
  BlockerGroup g;
  g.first = first;
  g.count = static_cast<std::uint32_t>(spheres.size());
  if (spheres.empty()) return g;
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const WorldSphere& s : spheres) {
    lo = glm::min(lo, s.centre - s.radius);
    hi = glm::max(hi, s.centre + s.radius);
  }
  g.bound.centre = 0.5f * (lo + hi);
  for (const WorldSphere& s : spheres)
    g.bound.radius = std::max(g.bound.radius, glm::length(s.centre - g.bound.centre) + s.radius);
  if (!(g.bound.radius > 0)) return g;
  constexpr int kGrid = 32;
  int inside = 0, covered = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) {
        const float x = g.bound.radius * (2 * (i + 0.5f) / kGrid - 1);
        const float y = g.bound.radius * (2 * (j + 0.5f) / kGrid - 1);
        if (x * x + y * y > g.bound.radius * g.bound.radius) continue;
        ++inside;
        for (const WorldSphere& s : spheres) {
          const float dx = g.bound.centre[u] + x - s.centre[u];
          const float dy = g.bound.centre[v] + y - s.centre[v];
          if (dx * dx + dy * dy <= s.radius * s.radius) {
            ++covered;
            break;
          }
        }
      }
  }
  g.coverage = inside > 0 ? std::max(0.01f, static_cast<float>(covered) / inside) : 1.0f;
  return g;
}

namespace {
// z_l = 2 pi N_l int_{-1}^{1} f(x) P_l(x) dx, midpoint rule in x = cos theta over 2^14 steps (the
// kinks of the clamped logs are resolved to ~1e-7).
template <int N, class F>
sh::Zonal<N> project_zonal(F&& f) {
  constexpr int kSteps = 1 << 14;
  double acc[N] = {};
  for (int i = 0; i < kSteps; ++i) {
    const double x = -1 + (i + 0.5) * 2.0 / kSteps;
    const double v = f(x);
    double p[N];
    sh::legendre(x, N, p);
    for (int l = 0; l < N; ++l) acc[l] += v * p[l];
  }
  sh::Zonal<N> z{};
  for (int l = 0; l < N; ++l) {
    const double norm = std::sqrt((2 * l + 1) / (4 * std::numbers::pi));
    z[l] = static_cast<float>(2 * std::numbers::pi * norm * acc[l] * 2.0 / kSteps);
  }
  return z;
}
}  // namespace

template <int N>
sh::Zonal<N> BlockerAccumulation<N>::log_diffuse_zh(float epsilon) {
  const double log_eps = std::log(static_cast<double>(epsilon));
  return project_zonal<N>([&](double x) {  // [Giraud] sec. 5, "Log-SH Diffuse"
    return std::max(std::log(std::max(x / std::numbers::pi, 1e-300)), log_eps);
  });
}

template <int N>
sh::Zonal<N> BlockerAccumulation<N>::log_phong_zh(float exponent, float epsilon) {
  const double log_eps = std::log(static_cast<double>(epsilon));
  const double k = (exponent + 1) / (2 * std::numbers::pi);
  return project_zonal<N>([&](double x) {  // [Giraud] eq. 27 (r: the Phong exponent)
    if (x <= 0) return log_eps;
    return std::max(std::log(k) + exponent * std::log(x), log_eps);
  });
}

template <int N>
sh::Zonal<N> BlockerAccumulation<N>::phong_zh(float exponent) {
  const double k = (exponent + 1) / (2 * std::numbers::pi);
  return project_zonal<N>([&](double x) { return x > 0 ? k * std::pow(x, exponent) : 0.0; });
}

template <int N>
float BlockerAccumulation<N>::fitted_phong_epsilon(float exponent) {
  const sh::Coeffs<N> lobe = sh::zonal_to_sh<N>(phong_zh(exponent));
  float best = 0.01f, best_err = std::numeric_limits<float>::infinity();
  for (int i = 0; i <= 64; ++i) {
    const float eps = 0.001f * std::pow(500.0f, i / 64.0f);  // 0.001 .. 0.5
    const sh::Coeffs<N> e = sh::exp_hyb<N>(sh::zonal_to_sh<N>(log_phong_zh(exponent, eps)));
    float err = 0;  // L2 over the sphere = over the coefficients
    for (int k = 0; k < N * N; ++k) err += (e[k] - lobe[k]) * (e[k] - lobe[k]);
    if (err < best_err) {
      best_err = err;
      best = eps;
    }
  }
  return best;
}

template <int N>
PhongLobe<N> BlockerAccumulation<N>::phong_lobe(float exponent, float epsilon) {
  if (!(exponent > 0 && std::isfinite(exponent)))
    throw std::invalid_argument("Phong exponent " + std::to_string(exponent) + " must be > 0");
  if (!(epsilon >= 0 && epsilon < 1))
    throw std::invalid_argument("Phong epsilon " + std::to_string(epsilon) +
                                " must be in [0, 1) (0: fitted)");
  PhongLobe<N> lobe;
  lobe.exponent = exponent;
  lobe.epsilon = epsilon > 0 ? epsilon : fitted_phong_epsilon(exponent);
  lobe.log_zh = log_phong_zh(exponent, lobe.epsilon);
  return lobe;
}

template <int N>
BlockerAccumulation<N>::BlockerAccumulation(const BlockerSettings& settings)
    : settings_(settings),
      log_eps_(std::log(settings.blocker.epsilon)),
      clamped_cosine_(sh::zh_clamped_cosine<N>()),
      log_diffuse_(log_diffuse_zh(settings.brdf_epsilon)),
      phong_(settings.phong_exponent > 0
                 ? phong_lobe(settings.phong_exponent, settings.phong_epsilon)
                 : PhongLobe<N>{}),
      cut_sin_(std::sin(80.0f / N * std::numbers::pi_v<float> / 180.0f)) {  // [Ren06] sec. 5
  const float eps = settings.blocker.epsilon;
  if (!(eps > 0 && eps < 1))
    throw std::invalid_argument("blocker epsilon " + std::to_string(eps) + " must be in (0, 1)");
  if (!(settings.brdf_epsilon > 0 && settings.brdf_epsilon < 1))
    throw std::invalid_argument("blocker brdf_epsilon must be in (0, 1)");
  if (!(settings.blocker.min_sin >= 0 && settings.blocker.min_sin < 1))
    throw std::invalid_argument("blocker min_sin must be in [0, 1)");
  if (settings.blocker.log == BlockerLog::kClippedEigen)
    clipped_log_ = std::make_shared<const ClippedLogCap<N>>(settings.blocker.eigen_clip);
}

template <int N>
float BlockerAccumulation<N>::add_blocker_log(const BlockerView& v, sh::Coeffs<N>& sum) const {
  if (!clipped_log_) {
    add_log_visibility<N>(v, log_eps_, sum);  // [Giraud] eq. 26, summed over blockers
    return 1;
  }
  add_log_visibility<N>(v, *clipped_log_, sum);  // [Ren06]: the clipped SH log
  // Depth at the axis of the widest cap, in units of log eps (bounds this cap's).
  return std::max(1.0f, clipped_log_->depth() / log_eps_);
}

template <int N>
void BlockerAccumulation<N>::set_blockers(std::vector<WorldSphere> spheres,
                                          std::vector<BlockerGroup> groups) {
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    if (!finite(spheres[i].centre))
      throw std::invalid_argument("blocker sphere " + std::to_string(i) + ": centre " +
                                  str(spheres[i].centre) + " is not finite");
    if (!(std::isfinite(spheres[i].radius) && spheres[i].radius >= 0))
      throw std::invalid_argument("blocker sphere " + std::to_string(i) + ": radius " +
                                  std::to_string(spheres[i].radius) + " must be finite and >= 0");
  }
  if (groups.empty()) {
    groups.reserve(spheres.size());
    for (std::uint32_t i = 0; i < spheres.size(); ++i) groups.push_back({spheres[i], i, 1, 1.0f});
  }
  std::uint32_t next = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (groups[g].first != next || groups[g].first + groups[g].count > spheres.size() ||
        !finite(groups[g].bound.centre) || !(groups[g].bound.radius >= 0) ||
        !(groups[g].coverage > 0 && groups[g].coverage <= 1))
      throw std::invalid_argument("blocker group " + std::to_string(g) +
                                  ": spheres out of order, bound not finite or coverage not in "
                                  "(0, 1]");
    next += groups[g].count;
  }
  if (next != spheres.size())
    throw std::invalid_argument("blocker groups cover " + std::to_string(next) + " of " +
                                std::to_string(spheres.size()) + " spheres");
  spheres_ = std::move(spheres);
  groups_ = std::move(groups);
  std::vector<WorldSphere> bounds(groups_.size());
  for (std::size_t g = 0; g < groups_.size(); ++g) bounds[g] = groups_[g].bound;
  grid_.build(bounds, settings_.blocker.min_sin);
}

template <int N>
void BlockerAccumulation<N>::set_lights(std::vector<LightSource> lights) {
  for (std::size_t i = 0; i < lights.size(); ++i)
    if (!finite(lights[i].centre) || !finite(lights[i].radiance) ||
        !(std::isfinite(lights[i].radius) && lights[i].radius >= 0))
      throw std::invalid_argument("light " + std::to_string(i) + ": centre " +
                                  str(lights[i].centre) + ", radius " +
                                  std::to_string(lights[i].radius) + " or radiance not valid");
  lights_ = std::move(lights);
}

template <int N>
template <class Add>
void BlockerAccumulation<N>::for_each_blocker(const glm::vec3& p, Add&& add) const {
  const bool cut = settings_.hierarchy == BlockerHierarchy::kObjects;
  const BlockerGrid::Candidates c = grid_.candidates(p);
  for (const auto list : {c.near, c.everywhere})
    for (const std::uint32_t gi : list) {
      const BlockerGroup& g = groups_[gi];
      if (g.count == 1) {
        add(spheres_[g.first], 1.0f);
        continue;
      }
      // [Ren06]: below the cut the bound stands for its spheres; over [cut, 1.25 cut] the two
      // are blended (in log space) so a receiver crossing the cut sees no step.
      const float d = glm::length(g.bound.centre - p);
      const float s = d > g.bound.radius ? g.bound.radius / d : 1.0f;
      const float a = cut ? std::clamp((s - cut_sin_) / (0.25f * cut_sin_), 0.0f, 1.0f) : 1.0f;
      if (a < 1) add(g.bound, g.coverage * (1 - a));
      if (a > 0)
        for (std::uint32_t i = g.first; i < g.first + g.count; ++i) add(spheres_[i], a);
    }
}

template <int N>
sh::Coeffs<N> BlockerAccumulation<N>::log_visibility(const glm::vec3& p, const glm::vec3& n,
                                                     PairCounts* counts) const {
  sh::Coeffs<N> sum{};
  const float max_depth = settings_.blocker.max_depth;
  PairCounts tally;
  float lowest = 0;     // the sum's lowest value at its blockers' axes, once the limit may apply
  if (!clipped_log_) {  // the eps cap: eight blockers per step (blocker_log_sum.h)
    BlockerLogSum<N> lanes(p, n, settings_.blocker, log_eps_);
    for_each_blocker(
        p, [&](const WorldSphere& s, float scale) { lanes.add(s.centre, s.radius, scale); });
    lanes.finish(sum);
    tally.views = lanes.views();
    tally.adds = lanes.adds();
    if (max_depth > 0 && lanes.weight() > max_depth) {  // else it cannot be that deep
      lowest = lanes.lowest_at_axes(sum);
      tally.depth_evaluations = static_cast<std::size_t>(lanes.axis_count());
    }
  } else {
    constexpr int kMaxAxes = 64;  // axes the depth limit looks at
    glm::vec3 axes[kMaxAxes];
    int count = 0;
    float weight = 0;
    for_each_blocker(p, [&](const WorldSphere& s, float scale) {
      BlockerView v = view_blocker(p, n, s.centre, s.radius, settings_.blocker);
      ++tally.views;
      v.weight *= scale;
      if (!(v.weight > 0)) return;
      weight += v.weight * add_blocker_log(v, sum);
      ++tally.adds;
      if (count < kMaxAxes) axes[count++] = v.axis;
    });
    if (max_depth > 0 && weight > max_depth) {
      float at[kMaxAxes];  // the sum at each axis, eight axes per step
      sh::evaluate_batch<N>(sum, std::span<const glm::vec3>(axes, static_cast<std::size_t>(count)),
                            std::span<float>(at, static_cast<std::size_t>(count)));
      for (int k = 0; k < count; ++k) lowest = std::min(lowest, at[k]);
      tally.depth_evaluations = static_cast<std::size_t>(count);
    }
  }
  if (counts) {
    counts->views += tally.views;
    counts->adds += tally.adds;
    counts->depth_evaluations += tally.depth_evaluations;
  }
  const float deepest = lowest / log_eps_;  // in units of log eps (positive)
  if (deepest > max_depth) {
    const float scale = max_depth / deepest;
    for (float& x : sum) x *= scale;
  }
  return sum;
}

template <int N>
sh::Coeffs<N> BlockerAccumulation<N>::visibility(const glm::vec3& p, const glm::vec3& n) const {
  return sh::exp_visibility<N>(log_visibility(p, n));
}

template <int N>
glm::vec3 BlockerAccumulation<N>::irradiance(const sh::CoeffsRgb<N>& radiance, const glm::vec3& p,
                                             const glm::vec3& n, sh::Coeffs<N>* visibility_out,
                                             const sh::Coeffs<N>* extra_log,
                                             bool with_lights) const {
  sh::Coeffs<N> log_v = log_visibility(p, n);
  if (extra_log)
    for (std::size_t i = 0; i < log_v.size(); ++i) log_v[i] += (*extra_log)[i];
  return irradiance_from_log(radiance, p, n, log_v, visibility_out, with_lights);
}

template <int N>
glm::vec3 BlockerAccumulation<N>::irradiance_from_log(const sh::CoeffsRgb<N>& radiance,
                                                      const glm::vec3& p, const glm::vec3& n,
                                                      const sh::Coeffs<N>& log_v,
                                                      sh::Coeffs<N>* visibility_out,
                                                      bool with_lights) const {
  sh::Coeffs<N> transfer;
  float scale = 1;
  if (settings_.shading == BlockerShading::kProduct) {
    const sh::Coeffs<N> v = sh::exp_visibility<N>(log_v);  // [Ren06]: one exponential
    if (visibility_out) *visibility_out = v;
    transfer = sh::product<N>(v, sh::rotate_zh<N>(clamped_cosine_, n));
  } else {
    sh::Coeffs<N> with_brdf = log_v;  // [Giraud] sec. 5: log-BRDF added before the exponential
    const sh::Coeffs<N> brdf = sh::rotate_zh<N>(log_diffuse_, n);
    for (std::size_t i = 0; i < with_brdf.size(); ++i) with_brdf[i] += brdf[i];
    transfer = sh::exp_visibility<N>(with_brdf);
    scale = std::numbers::pi_v<float>;  // the BRDF carried 1 / pi
    if (visibility_out) *visibility_out = sh::exp_visibility<N>(log_v);
  }
  sh::CoeffsRgb<N> seen = radiance;
  for (const LightSource& l : with_lights ? std::span<const LightSource>(lights_)
                                          : std::span<const LightSource>()) {  // [Meier13] eq. 4.27
    const glm::vec3 to = l.centre - p;
    const float d = glm::length(to);
    if (!(d > l.radius) || !(l.radius > 0)) continue;  // inside the light: nothing from it
    const sh::Coeffs<N> cap =
        sh::rotate_zh<N>(sh::zh_cap<N>(std::asin(std::min(1.0f, l.radius / d))), to / d);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < N * N; ++k) seen[c][k] += l.radiance[c] * cap[k];
  }
  return scale * glm::vec3(sh::dot<N>(seen[0], transfer), sh::dot<N>(seen[1], transfer),
                           sh::dot<N>(seen[2], transfer));
}

template <int N>
glm::vec3 BlockerAccumulation<N>::glossy_radiance(const sh::CoeffsRgb<N>& radiance,
                                                  const glm::vec3& p, const glm::vec3& n,
                                                  const glm::vec3& view) const {
  if (!(settings_.phong_exponent > 0))
    throw std::logic_error("glossy_radiance needs BlockerSettings::phong_exponent > 0");
  return glossy_radiance(radiance, p, n, view, phong_);
}

template <int N>
glm::vec3 BlockerAccumulation<N>::glossy_radiance(const sh::CoeffsRgb<N>& radiance,
                                                  const glm::vec3& p, const glm::vec3& n,
                                                  const glm::vec3& view, const PhongLobe<N>& phong,
                                                  const sh::Coeffs<N>* extra_log) const {
  const glm::vec3 r = 2 * glm::dot(n, view) * n - view;  // the reflected view direction
  sh::Coeffs<N> sum = log_visibility(p, n);
  if (extra_log)
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += (*extra_log)[i];
  const sh::Coeffs<N> lobe = sh::rotate_zh<N>(phong.log_zh, glm::normalize(r));
  for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += lobe[i];
  // [Giraud] sec. 5: one exponential, then a dot with the lighting. Not exp_visibility: the lobe
  // peaks at (r + 1) / 2 pi, above the [0, 1] its clamp assumes.
  const sh::Coeffs<N> s = sh::exp_hyb<N>(sum);
  return {sh::dot<N>(radiance[0], s), sh::dot<N>(radiance[1], s), sh::dot<N>(radiance[2], s)};
}

template <int N>
void BlockerAccumulation<N>::shade(const sh::CoeffsRgb<N>& radiance,
                                   std::span<const glm::vec3> points,
                                   std::span<const glm::vec3> normals,
                                   std::span<sh::Coeffs<N>> visibility,
                                   std::span<glm::vec3> irradiance_out) const {
  if (normals.size() != points.size() || irradiance_out.size() != points.size() ||
      (!visibility.empty() && visibility.size() != points.size()))
    throw std::invalid_argument("blocker shade: points, normals and outputs differ in size");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i]) || !finite(normals[i]))
      throw std::invalid_argument("receiver " + std::to_string(i) + ": point " + str(points[i]) +
                                  " or normal " + str(normals[i]) + " is not finite");
  }
  if (settings_.shading != BlockerShading::kProduct || !lights_.empty()) {
    for (std::size_t i = 0; i < points.size(); ++i)
      irradiance_out[i] = irradiance(radiance, points[i], normals[i],
                                     visibility.empty() ? nullptr : &visibility[i]);
    return;
  }
  // kProduct without lights: the sums per receiver, then the exponential, product and dots eight
  // receivers at a time on vector lanes (sh/batch.h; the same results as irradiance()).
  sh::CoeffsBatch<N> logs, v;
  sh::DirBatch dirs;
  float e[3][sh::kBatch];
  for (std::size_t first = 0; first < points.size(); first += sh::kBatch) {
    const int lanes = static_cast<int>(std::min<std::size_t>(sh::kBatch, points.size() - first));
    for (int l = 0; l < sh::kBatch; ++l) {
      const bool used = l < lanes;  // a partial batch: open-sky lanes
      logs.set(l, used ? log_visibility(points[first + l], normals[first + l]) : sh::Coeffs<N>{});
      dirs.set(l, used ? normals[first + l] : glm::vec3(0, 0, 1));
    }
    sh::exp_visibility_batch<N>(logs, v);
    sh::shade_zh_batch<N>(radiance, clamped_cosine_, v, dirs, e);
    for (int l = 0; l < lanes; ++l) {
      irradiance_out[first + l] = glm::vec3(e[0][l], e[1][l], e[2][l]);
      if (!visibility.empty()) visibility[first + l] = v.get(l);
    }
  }
}

namespace {
// Share of a disc of angular radius a covered by a cap of angular radius b whose centre is g
// away (small-angle: the planar lens area over pi a^2).
float disc_covered(float a, float b, float g) {
  if (g >= a + b) return 0.0f;
  if (!(a > 0)) return g < b ? 1.0f : 0.0f;
  if (g <= b - a) return 1.0f;
  if (g <= a - b) return (b * b) / (a * a);
  const float ca = std::clamp((g * g + a * a - b * b) / (2 * g * a), -1.0f, 1.0f);
  const float cb = std::clamp((g * g + b * b - a * a) / (2 * g * b), -1.0f, 1.0f);
  const float k = std::max(0.0f, (-g + a + b) * (g + a - b) * (g - a + b) * (g + a + b));
  const float lens = a * a * std::acos(ca) + b * b * std::acos(cb) - 0.5f * std::sqrt(k);
  return std::clamp(lens / (std::numbers::pi_v<float> * a * a), 0.0f, 1.0f);
}
}  // namespace

template <int N>
float BlockerAccumulation<N>::key_light_visibility(const glm::vec3& p, const glm::vec3& direction,
                                                   float angular_radius) const {
  float v = 1.0f;
  const BlockerGrid::Candidates c = grid_.candidates(p);
  const auto one = [&](std::uint32_t i) {
    const WorldSphere& s = spheres_[i];
    if (!(s.radius > 0)) return;
    const glm::vec3 to = s.centre - p;
    const float d = glm::length(to);
    if (d <= s.radius) {
      v = 0.0f;  // inside a blocker
      return;
    }
    const float cos_g = glm::dot(to, direction) / d;
    const float b = std::asin(s.radius / d);
    if (cos_g <= std::cos(std::min(b + angular_radius, std::numbers::pi_v<float>))) return;
    v *= 1.0f - disc_covered(angular_radius, b, std::acos(std::clamp(cos_g, -1.0f, 1.0f)));
  };
  // The grid holds the groups' bounds: a group whose bound's cap misses the disc is skipped
  // whole (its spheres lie inside the bound), else its spheres are tested.
  for (const auto list : {c.near, c.everywhere})
    for (const std::uint32_t gi : list) {
      const BlockerGroup& g = groups_[gi];
      const glm::vec3 to = g.bound.centre - p;
      const float d = glm::length(to);
      if (d > g.bound.radius) {
        const float b = std::asin(g.bound.radius / d);
        if (glm::dot(to, direction) / d <=
            std::cos(std::min(b + angular_radius, std::numbers::pi_v<float>)))
          continue;
      }
      for (std::uint32_t i = g.first; i < g.first + g.count && v > 0; ++i) one(i);
    }
  return v;
}

template class BlockerAccumulation<3>;
template class BlockerAccumulation<4>;
template class BlockerAccumulation<5>;
template class BlockerAccumulation<6>;

}  // namespace penumbra::blocker_accumulation
