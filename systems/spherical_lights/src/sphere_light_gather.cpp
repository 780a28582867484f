#include "penumbra/systems/spherical_lights/sphere_light_gather.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/rotation.h"

namespace penumbra::spherical_lights {
namespace {

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

float smoothstep01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3 - 2 * x);
}

// One SL as the receiver sees it (after the plane rule).
struct View {
  blocker_accumulation::BlockerView v;
  float angle;  // asin(sin_angle)
  float key0;   // order: object distance (kPerObject) or 0
  float key1;   // centre distance
  std::uint32_t light;
};

}  // namespace

template <int N>
SphereLightGather<N>::SphereLightGather(const SphereLightSettings& settings)
    : settings_(settings),
      log_eps_(std::log(std::max(settings.blocker.epsilon, 1e-6f))),
      clamped_cosine_(sh::zh_clamped_cosine<N>()) {}

template <int N>
void SphereLightGather<N>::set_lights(std::vector<SphereLightSource<N>> lights) {
  std::uint32_t objects = 0;
  emits_.assign(lights.size(), 0);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const SphereLightSource<N>& l = lights[i];
    bool ok_radiance = true, any = false;
    for (const auto& channel : l.radiance) {
      for (float c : channel) ok_radiance = ok_radiance && std::isfinite(c), any = any || c != 0;
    }
    if (!finite(l.centre) || !ok_radiance || !std::isfinite(l.radius) || l.radius < 0) {
      throw std::invalid_argument("spherical light " + std::to_string(i) +
                                  ": needs a finite centre and radiance and a finite radius >= 0");
    }
    emits_[i] = any ? 1 : 0;
    objects = std::max(objects, l.object + 1);
  }
  object_centres_.assign(objects, glm::vec3(0.0f));
  std::vector<int> members(objects, 0);
  for (const auto& l : lights) object_centres_[l.object] += l.centre, ++members[l.object];
  for (std::uint32_t o = 0; o < objects; ++o) {
    if (members[o] > 0) object_centres_[o] /= static_cast<float>(members[o]);
  }
  lights_ = std::move(lights);
}

template <int N>
glm::vec3 SphereLightGather<N>::irradiance(const glm::vec3& p, const glm::vec3& n,
                                           Counts* counts) const {
  if (!finite(p) || !finite(n)) {
    throw std::invalid_argument(
        "SphereLightGather::irradiance: non-finite receiver point or normal");
  }
  constexpr int kStack = 128;
  View stack[kStack];
  std::vector<View> heap;
  View* views = stack;
  if (lights_.size() > kStack) heap.resize(lights_.size()), views = heap.data();
  int count = 0;
  const bool per_object = settings_.blocking == SlBlocking::kPerObject;
  for (std::uint32_t i = 0; i < lights_.size(); ++i) {
    const SphereLightSource<N>& l = lights_[i];
    const blocker_accumulation::BlockerView v =
        blocker_accumulation::view_blocker(p, n, l.centre, l.radius, settings_.blocker);
    if (!(v.weight > 0)) continue;
    const float d = glm::length(l.centre - p);
    const float key0 = per_object ? glm::length(object_centres_[l.object] - p) : 0.0f;
    views[count++] = {v, std::asin(std::min(v.sin_angle, 1.0f)), key0, d, i};
  }
  if (counts) {
    counts->views += static_cast<std::size_t>(count);
    counts->lights += lights_.size();
  }
  // [Guerrero08] sec. 7.2 / 8.3: front to back, by sphere or by object then sphere.
  std::sort(views, views + count, [](const View& a, const View& b) {
    return a.key0 != b.key0 ? a.key0 < b.key0 : a.key1 < b.key1;
  });

  glm::vec3 total(0.0f);
  bool have_rho = false;
  sh::Coeffs<N> rho{};
  for (int i = 0; i < count; ++i) {
    const View& e = views[i];
    const SphereLightSource<N>& li = lights_[e.light];
    if (!emits_[e.light]) continue;
    if (counts) ++counts->emitters;
    // [Guerrero08] eq. 18, towards p in the SL's own frame (sec. 7.1).
    const glm::vec3 to_receiver = glm::normalize(li.to_local * -e.v.axis);
    const glm::vec3 radiance =
        glm::max(table_.average_radiance(li.radiance, e.v.sin_angle, to_receiver), glm::vec3(0.0f));
    if (radiance.x <= 0 && radiance.y <= 0 && radiance.z <= 0) continue;
    const float unblocked = cap_cosine_integral(e.v.sin_angle, glm::dot(n, e.v.axis));
    if (!(unblocked > 0)) continue;

    // Blockers in front whose caps overlap S_i's (header: ours), faded in over the overlap.
    sh::Coeffs<N> g{};
    bool any = false;
    for (int j = 0; j < i; ++j) {
      const View& b = views[j];
      const SphereLightSource<N>& lj = lights_[b.light];
      if (!lj.blocks) continue;
      if (counts) ++counts->pairs;
      if (lj.object == li.object && glm::length(lj.centre - li.centre) < lj.radius + li.radius) {
        continue;  // [Guerrero08] sec. 6.2: intersecting SLs of one object
      }
      const float between = std::acos(std::clamp(glm::dot(e.v.axis, b.v.axis), -1.0f, 1.0f));
      const float overlap = e.angle + b.angle - between;
      if (!(overlap > 0)) continue;
      blocker_accumulation::BlockerView faded = b.v;
      faded.weight *= smoothstep01(overlap / (0.25f * std::max(b.angle, 1e-6f)));
      if (!(faded.weight > 0)) continue;
      blocker_accumulation::add_log_visibility<N>(faded, log_eps_, g);
      if (counts) ++counts->logs;
      any = true;
    }
    float visibility = unblocked;
    if (any) {
      if (!have_rho) rho = sh::rotate_zh<N>(clamped_cosine_, n), have_rho = true;
      sh::Coeffs<N> gi{};
      blocker_accumulation::BlockerView own = e.v;
      own.weight = 1;
      blocker_accumulation::add_log_visibility<N>(own, log_eps_, gi);
      sh::Coeffs<N> g_all;
      for (int k = 0; k < N * N; ++k) g_all[k] = g[k] + gi[k];
      // [Guerrero08] eq. 23-24, less what they give with nothing in front (header).
      const sh::Coeffs<N> e_front = sh::exp_visibility<N>(g);
      const sh::Coeffs<N> e_all = sh::exp_visibility<N>(g_all);
      const sh::Coeffs<N> e_own = sh::exp_visibility<N>(gi);
      sh::Coeffs<N> diff;
      for (int k = 0; k < N * N; ++k) diff[k] = (e_front[k] - e_all[k]) - (-e_own[k]);
      diff[0] -= std::sqrt(4 * 3.14159265358979f);  // the constant 1
      const float scale = 1.0f / (1.0f - std::min(settings_.blocker.epsilon, 0.999f));
      visibility = std::clamp(unblocked + scale * sh::dot<N>(rho, diff), 0.0f, unblocked);
      if (counts) ++counts->blocked, counts->exponentials += 3, ++counts->logs;
    }
    total += e.v.weight * radiance * visibility;  // eq. 14
  }
  return total;
}

template <int N>
void SphereLightGather<N>::shade(std::span<const glm::vec3> points,
                                 std::span<const glm::vec3> normals,
                                 std::span<glm::vec3> irradiance_out) const {
  if (normals.size() != points.size() || irradiance_out.size() != points.size()) {
    throw std::invalid_argument(
        "SphereLightGather::shade: points, normals and output differ in size");
  }
  for (std::size_t i = 0; i < points.size(); ++i)
    irradiance_out[i] = irradiance(points[i], normals[i]);
}

template class SphereLightGather<3>;
template class SphereLightGather<4>;
template class SphereLightGather<5>;

}  // namespace penumbra::spherical_lights
