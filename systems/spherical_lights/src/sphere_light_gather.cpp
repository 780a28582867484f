#include "penumbra/systems/spherical_lights/sphere_light_gather.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "penumbra/data/finite.h"
#include "penumbra/sh/batch.h"
#include "penumbra/sh/exp_log.h"
#include "penumbra/sh/lanes.h"
#include "penumbra/sh/rotation.h"

namespace penumbra::spherical_lights {
namespace {

using data::finite;

float smoothstep01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3 - 2 * x);
}

// The SL (c, r) as an emitter seen from p with unit normal n under EmitterHorizon::kClip
// (sphere_light_gather.h): the whole sphere from 1.25 radii out, the plane rule's sphere inside
// it, and the two blended (centre, radius and weight) between.
blocker_accumulation::BlockerView emitter_view(const glm::vec3& p, const glm::vec3& n,
                                               const glm::vec3& c, float r,
                                               const blocker_accumulation::BlockerView& plane,
                                               float min_sin) {
  blocker_accumulation::BlockerView v;
  if (!(r > 0)) return v;
  const float d = glm::length(c - p);
  const float s = smoothstep01((d / r - 1.0f) * 4.0f);  // 0 inside, 1 from 1.25 r
  if (s <= 0) return plane;
  const float t = glm::dot(n, c - p) + r;
  if (!(t > 0)) return v;  // wholly below the plane: no light either way
  const float r1 = std::min(r, 0.5f * t);
  const glm::vec3 c1 = c + (r - r1) * n;  // the plane rule's sphere (sphere_blocker.cpp)
  const glm::vec3 cb = c1 + s * (c - c1);
  const float rb = r1 + s * (r - r1);
  const float db = glm::length(cb - p);
  if (!(db > 0)) return v;
  v.axis = (cb - p) / db;
  v.sin_angle = std::min(rb / db, 1.0f);
  v.weight = smoothstep01(t / (2 * r));
  v.weight += s * (1.0f - v.weight);
  if (min_sin > 0) v.weight *= smoothstep01((v.sin_angle - min_sin) / min_sin);
  return v;
}

// sum_l k_l z_l P_l(x): the dot of two zonal functions turned to directions at cosine x
// (addition theorem with rotate_zh's sqrt(4 pi / (2l + 1)) normalisation).
template <int N>
float zonal_dot(const sh::Zonal<N>& k, const sh::Zonal<N>& z, float x) {
  float p0 = 1, p1 = x, sum = k[0] * z[0];
  if (N > 1) sum += k[1] * z[1] * x;
  for (int l = 2; l < N; ++l) {
    const float p2 = ((2 * l - 1) * x * p1 - (l - 1) * p0) / static_cast<float>(l);
    sum += k[l] * z[l] * p2;
    p0 = p1, p1 = p2;
  }
  return sum;
}

}  // namespace

// One SL as the receiver sees it (after the plane rule).
template <int N>
struct SphereLightGather<N>::View {
  blocker_accumulation::BlockerView v;   // as a blocker (the plane rule)
  blocker_accumulation::BlockerView ev;  // as an emitter (EmitterHorizon)
  float ecos;                            // sqrt(1 - ev.sin_angle^2)
  float cos_angle;                       // sqrt(1 - sin_angle^2)
  float angle;  // asin(sin_angle), computed when first needed (< 0: not yet)
  float key0;   // order: object distance (kPerObject) or 0
  float key1;   // centre distance
  std::uint32_t light;
  // As an emitter, when `ready` (the lanes of shade_cluster): eq. 18's L~ (clamped at 0), the
  // cosine of its axis with the normal and the unblocked cap integral; else computed when shaded.
  bool ready;
  glm::vec3 radiance;
  float cos_n, unblocked;
  float angle_of() {
    if (angle < 0) angle = std::asin(std::min(v.sin_angle, 1.0f));
    return angle;
  }
};

template <int N>
SphereLightGather<N>::SphereLightGather(const SphereLightSettings& settings)
    : settings_(settings),
      log_eps_(std::log(std::max(settings.blocker.epsilon, 1e-6f))),
      table_(settings.radiance_weight),
      clamped_cosine_(sh::zh_clamped_cosine<N>()) {
  cap_exp_.resize((kExpSin + 1) * (kExpWeight + 1));
  for (int i = 0; i <= kExpSin; ++i) {
    for (int j = 0; j <= kExpWeight; ++j) {
      blocker_accumulation::BlockerView v;
      v.sin_angle = std::min(static_cast<float>(i) / kExpSin, 1.0f);
      v.weight = static_cast<float>(j) / kExpWeight;
      sh::Coeffs<N> g{};
      blocker_accumulation::add_log_visibility<N>(v, log_eps_, g);
      const sh::Coeffs<N> e = sh::exp_visibility<N>(g);
      sh::Zonal<N>& z = cap_exp_[i * (kExpWeight + 1) + j];
      for (int l = 0; l < N; ++l) z[l] = e[sh::index(l, 0)];  // at +z: f_l0 = z_l
    }
  }
}

template <int N>
sh::Zonal<N> SphereLightGather<N>::cap_exp_zonal(float sin_angle, float weight) const {
  const float x = std::clamp(sin_angle, 0.0f, 1.0f) * kExpSin;
  const float y = std::clamp(weight, 0.0f, 1.0f) * kExpWeight;
  const int i = std::min(static_cast<int>(x), kExpSin - 1);
  const int j = std::min(static_cast<int>(y), kExpWeight - 1);
  const float fx = x - static_cast<float>(i), fy = y - static_cast<float>(j);
  const sh::Zonal<N>* row0 = &cap_exp_[i * (kExpWeight + 1) + j];
  const sh::Zonal<N>* row1 = row0 + (kExpWeight + 1);
  sh::Zonal<N> z;
  for (int l = 0; l < N; ++l) {
    const float a = row0[0][l] + fy * (row0[1][l] - row0[0][l]);
    const float b = row1[0][l] + fy * (row1[1][l] - row1[0][l]);
    z[l] = a + fx * (b - a);
  }
  return z;
}

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
  object_radius_.assign(objects, 0.0f);
  object_first_.assign(objects + 1, 0);
  for (const auto& l : lights) {
    object_radius_[l.object] = std::max(
        object_radius_[l.object], glm::length(l.centre - object_centres_[l.object]) + l.radius);
    ++object_first_[l.object + 1];
  }
  for (std::uint32_t o = 0; o < objects; ++o) {
    object_first_[o + 1] += object_first_[o];
    object_radius_[o] *= 1.0001f;  // rounding: the bound must contain its SLs
  }
  object_lights_.assign(lights.size(), 0);
  std::vector<std::uint32_t> next(object_first_.begin(), object_first_.end() - 1);
  for (std::uint32_t i = 0; i < lights.size(); ++i) object_lights_[next[lights[i].object]++] = i;
  lights_ = std::move(lights);
}

template <int N>
glm::vec3 SphereLightGather<N>::irradiance(const glm::vec3& p, const glm::vec3& n,
                                           Counts* counts) const {
  if (!finite(p) || !finite(n)) {
    throw std::invalid_argument(
        "SphereLightGather::irradiance: non-finite receiver point or normal");
  }
  return evaluate(p, n, counts, nullptr, nullptr, settings_.blocker.min_sin);
}

template <int N>
glm::vec3 SphereLightGather<N>::evaluate(const glm::vec3& p, const glm::vec3& n, Counts* counts,
                                         const std::uint8_t* skip, glm::vec3* ratio_out,
                                         float min_sin, const std::uint8_t* consider) const {
  blocker_accumulation::SphereBlockerSettings blocker = settings_.blocker;
  blocker.min_sin = min_sin;
  // Scratch kept per thread: a local array would be constructed (zeroed) at every receiver.
  thread_local std::vector<View> scratch;
  if (scratch.size() < lights_.size()) scratch.resize(lights_.size());
  View* views = scratch.data();
  int count = 0;
  const bool per_object = settings_.blocking == SlBlocking::kPerObject;
  const bool clip = settings_.horizon == EmitterHorizon::kClip;
  std::size_t looked = 0;
  for (std::uint32_t o = 0; o + 1 < object_first_.size(); ++o) {
    // The object's bound first (header: ours): exact when p is outside it.
    const glm::vec3 to_bound = object_centres_[o] - p;
    const float bound_d2 = glm::dot(to_bound, to_bound), bound_r = object_radius_[o];
    if (bound_d2 > bound_r * bound_r) {
      if (glm::dot(n, to_bound) + bound_r <= 0) continue;
      if (min_sin > 0 && bound_r * bound_r <= min_sin * min_sin * bound_d2) continue;
    }
    const float key0 = per_object ? std::sqrt(bound_d2) : 0.0f;
    for (std::uint32_t k = object_first_[o]; k < object_first_[o + 1]; ++k) {
      const std::uint32_t i = object_lights_[k];
      if (consider && !consider[i]) continue;
      const SphereLightSource<N>& l = lights_[i];
      ++looked;
      const blocker_accumulation::BlockerView v =
          blocker_accumulation::view_blocker(p, n, l.centre, l.radius, blocker);
      const blocker_accumulation::BlockerView ev =
          clip && emits_[i] ? emitter_view(p, n, l.centre, l.radius, v, min_sin) : v;
      if (!(v.weight > 0) && !(ev.weight > 0)) continue;
      const float d = glm::length(l.centre - p);
      const float s = std::min(v.sin_angle, 1.0f), es = std::min(ev.sin_angle, 1.0f);
      views[count++] = {v,
                        ev,
                        std::sqrt(std::max(0.0f, 1 - es * es)),
                        std::sqrt(std::max(0.0f, 1 - s * s)),
                        -1.0f,
                        key0,
                        d,
                        i,
                        false,
                        glm::vec3(0.0f),
                        0.0f,
                        0.0f};
    }
  }
  if (counts) counts->lights += looked;
  return shade_views(n, views, count, counts, skip, ratio_out);
}

template <int N>
glm::vec3 SphereLightGather<N>::shade_views(const glm::vec3& n, View* views, int count,
                                            Counts* counts, const std::uint8_t* skip,
                                            glm::vec3* ratio_out) const {
  if (counts) counts->views += static_cast<std::size_t>(count);
  // [Guerrero08] sec. 7.2 / 8.3: front to back, by sphere or by object then sphere.
  std::sort(views, views + count, [](const View& a, const View& b) {
    return a.key0 != b.key0 ? a.key0 < b.key0 : a.key1 < b.key1;
  });

  glm::vec3 total(0.0f);
  struct Pending {
    std::uint32_t light;
    float unblocked, partial;  // partial: the table terms of the difference
    glm::vec3 light_weighted, radiance;
    int front, all;  // exp_in entries (front < 0: from the table)
  };
  thread_local std::vector<Pending> pending;
  thread_local std::vector<sh::Coeffs<N>> exp_in, exp_out;
  pending.clear();
  exp_in.clear();
  const float sqrt_4pi = std::sqrt(4 * 3.14159265358979f);
  const float scale = 1.0f / (1.0f - std::min(settings_.blocker.epsilon, 0.999f));
  for (int i = 0; i < count; ++i) {
    View& e = views[i];
    const SphereLightSource<N>& li = lights_[e.light];
    if (!emits_[e.light] || (skip && skip[e.light])) continue;
    if (counts) ++counts->emitters;
    if (!e.ready) {
      // [Guerrero08] eq. 18, towards p in the SL's own frame (sec. 7.1).
      const glm::vec3 to_receiver = glm::normalize(li.to_local * -e.ev.axis);
      e.radiance = glm::max(table_.average_radiance(li.radiance, e.ev.sin_angle, to_receiver),
                            glm::vec3(0.0f));
      e.cos_n = glm::dot(n, e.ev.axis);
      e.unblocked = cap_cosine_integral(e.ev.sin_angle, e.cos_n);
    }
    const glm::vec3 radiance = e.radiance;
    const float cos_n = e.cos_n, unblocked = e.unblocked;
    if (ratio_out) ratio_out[e.light] = glm::vec3(0.0f);  // seen here
    if (radiance.x <= 0 && radiance.y <= 0 && radiance.z <= 0) continue;
    if (!(unblocked > 0)) continue;

    // Blockers in front whose caps overlap S_i's (header: ours), faded in over the overlap.
    sh::Coeffs<N> g{};
    int added = 0;
    blocker_accumulation::BlockerView lone{};
    for (int j = 0; j < i; ++j) {
      View& b = views[j];
      const SphereLightSource<N>& lj = lights_[b.light];
      if (!lj.blocks) continue;
      if (counts) ++counts->pairs;
      // Overlap: the angle between the axes is below the sum of the half-angles, i.e. its cosine
      // is above cos(a_i + a_j) (always when the sum passes pi).
      const float cos_between = glm::dot(e.ev.axis, b.v.axis);
      const float cos_sum = e.ecos * b.cos_angle - e.ev.sin_angle * b.v.sin_angle;
      const bool wide = e.ecos * b.v.sin_angle + e.ev.sin_angle * b.cos_angle < 0;  // sum > pi
      if (!wide && !(cos_between > cos_sum)) continue;
      if (lj.object == li.object && glm::length(lj.centre - li.centre) < lj.radius + li.radius) {
        continue;  // [Guerrero08] sec. 6.2: intersecting SLs of one object
      }
      const float between = std::acos(std::clamp(cos_between, -1.0f, 1.0f));
      const float overlap = std::asin(std::min(e.ev.sin_angle, 1.0f)) + b.angle_of() - between;
      if (!(overlap > 0)) continue;
      blocker_accumulation::BlockerView faded = b.v;
      faded.weight *= smoothstep01(overlap / (0.25f * std::max(b.angle, 1e-6f)));
      if (!(faded.weight > 0)) continue;
      blocker_accumulation::add_log_visibility<N>(faded, log_eps_, g);
      if (counts) ++counts->logs;
      lone = faded;
      ++added;
    }
    if (added == 0) {
      if (ratio_out) ratio_out[e.light] = radiance;  // V~ = C
      total += e.ev.weight * radiance * unblocked;   // eq. 14
      continue;
    }
    blocker_accumulation::BlockerView own = e.ev;
    own.weight = 1;
    // [Guerrero08] eq. 23-24, less what they give with nothing in front (header): exp(G_i)
    // and, with one blocker, exp(G) from the table of lone caps; the SH exponentials are
    // deferred and taken 8 lanes at a time below.
    Pending q;
    q.light = e.light;
    q.unblocked = unblocked;
    q.light_weighted = e.ev.weight * radiance;
    q.radiance = radiance;
    q.partial = zonal_dot<N>(clamped_cosine_, cap_exp_zonal(e.ev.sin_angle, 1.0f), cos_n) -
                clamped_cosine_[0] * sqrt_4pi;
    q.front = -1;
    if (added == 1) {
      q.partial += zonal_dot<N>(clamped_cosine_, cap_exp_zonal(lone.sin_angle, lone.weight),
                                glm::dot(n, lone.axis));
    } else {
      q.front = static_cast<int>(exp_in.size());
      exp_in.push_back(g);
    }
    blocker_accumulation::add_log_visibility<N>(own, log_eps_, g);  // g = G + G_i
    q.all = static_cast<int>(exp_in.size());
    exp_in.push_back(g);
    pending.push_back(q);
    if (counts) {
      ++counts->blocked, ++counts->logs;
      counts->exponentials += added == 1 ? 1 : 2;
    }
  }
  if (pending.empty()) return total;
  const sh::Coeffs<N> rho = sh::rotate_zh<N>(clamped_cosine_, n);
  exp_out.resize(exp_in.size());
  sh::exp_visibility_batch<N>(exp_in, exp_out);
  for (const Pending& q : pending) {
    float diff = q.partial - sh::dot<N>(rho, exp_out[q.all]);
    if (q.front >= 0) diff += sh::dot<N>(rho, exp_out[q.front]);
    const float visibility = std::clamp(q.unblocked + scale * diff, 0.0f, q.unblocked);
    if (ratio_out) ratio_out[q.light] = q.radiance * (visibility / q.unblocked);
    total += q.light_weighted * visibility;  // eq. 14
  }
  return total;
}

template <int N>
void SphereLightGather<N>::view_lanes(const float* const* receiver,
                                      std::span<const std::uint32_t> lights,
                                      const std::uint8_t* skip, float* out) const {
  // view_blocker (sphere_blocker.cpp) and evaluate()'s emitter terms, 8 receivers a lane step.
  using sh::Lanes;
  constexpr int W = sh::kLaneCount;
  const Lanes x = sh::load_lanes(receiver[0]), y = sh::load_lanes(receiver[1]),
              z = sh::load_lanes(receiver[2]), u = sh::load_lanes(receiver[3]),
              v = sh::load_lanes(receiver[4]), w = sh::load_lanes(receiver[5]);
  const float min_sin = settings_.blocker.min_sin;
  const bool ratio = settings_.blocker.ratio == blocker_accumulation::RatioAttenuation::kOn;
  const bool per_object = settings_.blocking == SlBlocking::kPerObject;
  const auto smooth = [](Lanes a) {
    a = sh::lane_clamp01(a);
    return a * a * (sh::splat(3) - sh::splat(2) * a);
  };
  float band[N];  // rotate_zh's sqrt(4 pi / (2l + 1))
  for (int l = 0; l < N; ++l)
    band[l] = std::sqrt(4 * std::numbers::pi_v<float> / static_cast<float>(2 * l + 1));
  for (std::size_t k = 0; k < lights.size(); ++k) {
    const std::uint32_t i = lights[k];
    const SphereLightSource<N>& l = lights_[i];
    float* f = out + k * kLaneFields * W;
    const Lanes r = sh::splat(l.radius);
    const Lanes cx = sh::splat(l.centre.x) - x, cy = sh::splat(l.centre.y) - y,
                cz = sh::splat(l.centre.z) - z;
    const Lanes t = u * cx + v * cy + w * cz + r;  // reach above the tangent plane
    const Lanes r1 = sh::lane_min(r, sh::splat(0.5f) * t);
    const Lanes shift = r - r1;
    const Lanes tx = cx + shift * u, ty = cy + shift * v, tz = cz + shift * w;
    const Lanes d1 = sh::lane_sqrt(tx * tx + ty * ty + tz * tz);
    const sh::LaneMask ok = (t > 0) & (d1 > 0);
    const Lanes inv = sh::splat(1.0f) / sh::select(d1 > 0, d1, sh::splat(1.0f));
    const Lanes ax = tx * inv, ay = ty * inv, az = tz * inv;
    const Lanes sin = sh::lane_min(r1 * inv, sh::splat(1.0f));
    Lanes weight = smooth(t / (sh::splat(2) * r));
    if (min_sin > 0) weight *= smooth((sin - sh::splat(min_sin)) * sh::splat(1 / min_sin));
    if (ratio) weight *= sin;
    weight = sh::select(ok, weight, Lanes{});
    sh::store_lanes(ax, f), sh::store_lanes(ay, f + W), sh::store_lanes(az, f + 2 * W);
    sh::store_lanes(sin, f + 3 * W), sh::store_lanes(weight, f + 4 * W);
    sh::store_lanes(sh::lane_sqrt(sh::splat(1.0f) - sin * sin), f + 5 * W);
    Lanes key0{};
    if (per_object) {
      const glm::vec3 b = object_centres_[l.object];
      const Lanes bx = sh::splat(b.x) - x, by = sh::splat(b.y) - y, bz = sh::splat(b.z) - z;
      key0 = sh::lane_sqrt(bx * bx + by * by + bz * bz);
    }
    sh::store_lanes(key0, f + 6 * W);
    sh::store_lanes(sh::lane_sqrt(cx * cx + cy * cy + cz * cz), f + 7 * W);
    if (!emits_[i] || (skip && skip[i]) || !(sh::lane_bits(weight > 0) != 0)) continue;
    // [Guerrero08] eq. 18 towards the receivers in the SL's own frame (sec. 7.1): the basis at
    // to_local * -axis, each band scaled by w_theta's weight (rotate_zh) and dotted with L^c.
    const glm::mat3& m = l.to_local;
    Lanes dx = -(sh::splat(m[0][0]) * ax + sh::splat(m[1][0]) * ay + sh::splat(m[2][0]) * az);
    Lanes dy = -(sh::splat(m[0][1]) * ax + sh::splat(m[1][1]) * ay + sh::splat(m[2][1]) * az);
    Lanes dz = -(sh::splat(m[0][2]) * ax + sh::splat(m[1][2]) * ay + sh::splat(m[2][2]) * az);
    const Lanes len = sh::lane_sqrt(dx * dx + dy * dy + dz * dz);
    const Lanes inv_len = sh::splat(1.0f) / sh::select(len > 0, len, sh::splat(1.0f));
    dx *= inv_len, dy *= inv_len, dz *= inv_len;
    Lanes basis[N * N];
    sh::eval_basis_lanes<N>(dx, dy, dz, basis);
    float sins[W];
    sh::store_lanes(sin, sins);
    Lanes zonal[N];
    for (int j = 0; j < W; ++j) {
      const sh::Zonal<N> zw = table_.weights(sins[j]);
      for (int b = 0; b < N; ++b) zonal[b][j] = band[b] * zw[b];
    }
    for (int c = 0; c < 3; ++c) {
      Lanes sum{};
      for (int b = 0; b < N; ++b) {
        Lanes dot{};
        for (int q = b * b; q < (b + 1) * (b + 1); ++q) dot += basis[q] * l.radiance[c][q];
        sum += zonal[b] * dot;
      }
      sh::store_lanes(sh::lane_max(sum, Lanes{}), f + (8 + c) * W);
    }
    const Lanes cos_n = u * ax + v * ay + w * az;
    sh::store_lanes(cos_n, f + 11 * W);
    sh::store_lanes(cap_cosine_integral_lanes(sin, cos_n), f + 12 * W);
  }
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

namespace {

// Key of a receiver's cell of size `cell` (21 bits per axis, wrapped) and its normal's dominant
// axis and sign.
std::uint64_t cell_key(const glm::vec3& p, const glm::vec3& n, float cell) {
  const glm::vec3 q = glm::floor(p / cell);
  const glm::vec3 a = glm::abs(n);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const std::uint64_t side = n[axis] < 0 ? 1 : 0;
  auto bits = [](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(v) & 0x1fffff);
  };
  return (bits(q.x) << 42 | bits(q.y) << 21 | bits(q.z)) << 3 |
         static_cast<std::uint64_t>(axis * 2) | side;
}

// Centre, normal, radius, thickness, spread and planarity of every cluster of `level`.
void cluster_geometry(const SlReceiverClusters& c, const SlClusterSettings& settings,
                      SlClusterLevel& level) {
  const std::size_t clusters = level.size();
  level.centre.assign(clusters, glm::vec3(0.0f));
  level.normal.assign(clusters, glm::vec3(0.0f));
  level.radius.assign(clusters, 0.0f);
  level.thickness.assign(clusters, 0.0f);
  level.spread.assign(clusters, 0.0f);
  level.planar.assign(clusters, 0);
  for (std::size_t k = 0; k < clusters; ++k) {
    glm::vec3 sum_p(0.0f), sum_n(0.0f);
    for (std::uint32_t j = level.first[k]; j < level.first[k + 1]; ++j)
      sum_p += c.points[j], sum_n += c.normals[j];
    const float count = static_cast<float>(level.first[k + 1] - level.first[k]);
    level.centre[k] = sum_p / count;
    level.normal[k] = glm::length(sum_n) > 0 ? glm::normalize(sum_n) : glm::vec3(0, 0, 1);
    float r = 0, min_cos = 1, thick = 0;
    for (std::uint32_t j = level.first[k]; j < level.first[k + 1]; ++j) {
      r = std::max(r, glm::length(c.points[j] - level.centre[k]));
      min_cos = std::min(min_cos, glm::dot(c.normals[j], level.normal[k]));
      thick = std::max(thick, std::abs(glm::dot(level.normal[k], c.points[j] - level.centre[k])));
    }
    level.radius[k] = r * 1.0001f;
    level.thickness[k] = thick * 1.0001f + 1e-6f;
    level.spread[k] = std::sqrt(std::max(0.0f, 2 - 2 * min_cos)) + 1e-6f;
    level.planar[k] = min_cos >= settings.normal_cos && thick <= 1e-3f * std::max(r, 1e-3f) + 1e-4f;
  }
}

}  // namespace

SlReceiverClusters cluster_receivers(std::span<const glm::vec3> points,
                                     std::span<const glm::vec3> normals,
                                     const SlClusterSettings& settings) {
  if (normals.size() != points.size()) {
    throw std::invalid_argument("cluster_receivers: points and normals differ in size");
  }
  if (!(settings.cell > 0) || settings.max_receivers < 1) {
    throw std::invalid_argument("cluster_receivers: needs cell > 0 and max_receivers >= 1");
  }
  SlReceiverClusters c;
  c.settings = settings;
  struct Keyed {
    std::uint64_t coarse, fine;
    std::uint32_t index;
    bool operator<(const Keyed& o) const {
      return coarse != o.coarse ? coarse < o.coarse
             : fine != o.fine   ? fine < o.fine
                                : index < o.index;
    }
  };
  std::vector<Keyed> keyed(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i]) || !finite(normals[i])) {
      throw std::invalid_argument("cluster_receivers: receiver " + std::to_string(i) +
                                  " has a non-finite point or normal");
    }
    keyed[i] = {cell_key(points[i], normals[i], settings.cell),
                cell_key(points[i], normals[i], 0.5f * settings.cell), i};
  }
  std::sort(keyed.begin(), keyed.end());
  c.order.reserve(points.size());
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    const bool new_coarse = k == 0 || keyed[k].coarse != keyed[k - 1].coarse;
    const bool new_fine =
        new_coarse || keyed[k].fine != keyed[k - 1].fine ||
        c.order.size() - c.fine.first.back() >= static_cast<std::size_t>(settings.max_receivers);
    const auto at = static_cast<std::uint32_t>(c.order.size());
    if (new_coarse) {
      c.coarse.first.push_back(at);
      c.children.push_back(static_cast<std::uint32_t>(c.fine.first.size()));
    }
    if (new_fine) c.fine.first.push_back(at);
    c.order.push_back(keyed[k].index);
  }
  const auto total = static_cast<std::uint32_t>(c.order.size());
  if (!keyed.empty()) {
    c.coarse.first.push_back(total);
    c.fine.first.push_back(total);
    c.children.push_back(static_cast<std::uint32_t>(c.fine.first.size() - 1));
  }
  c.points.resize(c.order.size());
  c.normals.resize(c.order.size());
  for (std::size_t j = 0; j < c.order.size(); ++j) {
    c.points[j] = points[c.order[j]];
    c.normals[j] = glm::normalize(normals[c.order[j]]);
  }
  cluster_geometry(c, settings, c.coarse);
  cluster_geometry(c, settings, c.fine);
  return c;
}

template <int N>
bool SphereLightGather<N>::has_near(const SlClusterLevel& level, std::size_t k,
                                    float far_ratio) const {
  // The classification of shade_cluster, without the centre's evaluation.
  const glm::vec3 centre = level.centre[k], normal = level.normal[k];
  const float radius = level.radius[k], min_sin = settings_.blocker.min_sin;
  for (std::size_t i = 0; i < lights_.size(); ++i) {
    const SphereLightSource<N>& l = lights_[i];
    if (!emits_[i] || !(l.radius > 0)) continue;
    const glm::vec3 to = l.centre - centre;
    const float d = glm::length(to);
    const bool outside = d > radius + l.radius;
    const bool below =
        glm::dot(normal, to) + l.radius + level.thickness[k] + level.spread[k] * (d + radius) <= 0;
    const bool small = min_sin > 0 && outside && l.radius <= min_sin * (d - radius);
    if (outside && (below || small)) continue;
    const float t = glm::dot(normal, to) + l.radius;
    if (!(t > 0)) return true;
    const float r1 = std::min(l.radius, 0.5f * t);
    const glm::vec3 c1 = l.centre + (l.radius - r1) * normal;
    const float d1 = glm::length(c1 - centre);
    const float vary = level.thickness[k] + level.spread[k] * (d1 + radius);
    if (settings_.horizon == EmitterHorizon::kClip && t - vary < 2 * l.radius) return true;
    if (!(r1 > 0 && radius <= far_ratio * (d1 - r1) && vary <= 0.01f * r1)) return true;
  }
  return false;
}

template <int N>
void SphereLightGather<N>::shade_coarse(const SlReceiverClusters& clusters, std::size_t k,
                                        std::span<glm::vec3> out, Counts* counts) const {
  if (clusters.coarse.planar[k] && !has_near(clusters.coarse, k, clusters.settings.far_ratio)) {
    shade_cluster(clusters, clusters.coarse, k, out, counts);
    return;
  }
  for (std::uint32_t f = clusters.children[k]; f < clusters.children[k + 1]; ++f)
    shade_cluster(clusters, clusters.fine, f, out, counts);
}

template <int N>
void SphereLightGather<N>::shade_cluster(const SlReceiverClusters& clusters,
                                         const SlClusterLevel& level, std::size_t k,
                                         std::span<glm::vec3> out, Counts* counts) const {
  const std::uint32_t begin = level.first[k], end = level.first[k + 1];
  const std::size_t lights = lights_.size();
  const float min_sin = settings_.blocker.min_sin;
  if (!level.planar[k] || lights == 0) {
    for (std::uint32_t j = begin; j < end; ++j)
      out[clusters.order[j]] =
          evaluate(clusters.points[j], clusters.normals[j], counts, nullptr, nullptr, min_sin);
    return;
  }
  // [Guerrero08] sec. 7.3, eq. 25-26 in spirit (header: ours): in a planar cluster the plane
  // rule's shrunk sphere (sec. 6.2) is the same at every receiver; a far one carries the ratio
  // L~ V~ / C measured at the cluster's centre, and every receiver multiplies it by its own exact
  // cap integral C (the shrunk cap is wholly above the plane, so C = pi sin^2 cos beta).
  const glm::vec3 centre = level.centre[k], normal = level.normal[k];
  const float radius = level.radius[k];
  thread_local std::vector<std::uint8_t> far;
  thread_local std::vector<glm::vec3> ratio;
  far.assign(lights, 0);
  ratio.assign(lights, glm::vec3(-1.0f));
  struct Shrunk {
    glm::vec3 centre;
    float radius, plane_weight;
    bool far;
  };
  thread_local std::vector<Shrunk> shrunk;
  shrunk.assign(lights, Shrunk{});
  bool any_far = false;
  for (std::size_t i = 0; i < lights; ++i) {
    const SphereLightSource<N>& l = lights_[i];
    if (!emits_[i] || !(l.radius > 0)) continue;
    const float t = glm::dot(normal, l.centre - centre) + l.radius;  // sphere_blocker.cpp
    if (!(t > 0)) continue;
    const float r1 = std::min(l.radius, 0.5f * t);
    const glm::vec3 c1 = l.centre + (l.radius - r1) * normal;
    const float d1 = glm::length(c1 - centre);
    // The shrunk cap touches or clears the centre's plane; every receiver's plane is within
    // `vary` of it, so its own shrunk sphere differs by at most 1% of r1.
    const float vary = level.thickness[k] + level.spread[k] * (d1 + radius);
    // Under kClip only a sphere wholly above every receiver's plane is far (the plane rule then
    // leaves it whole, so the far path's cap is the emitter's own).
    const bool above = settings_.horizon != EmitterHorizon::kClip || t - vary >= 2 * l.radius;
    const bool is_far =
        above && r1 > 0 && radius <= clusters.settings.far_ratio * (d1 - r1) && vary <= 0.01f * r1;
    shrunk[i] = {c1, r1, smoothstep01(t / (2 * l.radius)), is_far};
    far[i] = is_far ? 1 : 0;
    any_far = any_far || is_far;
  }
  // At the centre down to half min_sin: an SL its receivers see may be just below it there.
  if (any_far) evaluate(centre, normal, counts, nullptr, ratio.data(), 0.5f * min_sin);
  struct Far {
    glm::vec3 centre;
    float r2;
    glm::vec3 ratio;  // L~ V~ / C x the plane rule's weight
    std::uint32_t object;
  };
  thread_local std::vector<Far> far_list;
  thread_local std::vector<std::uint8_t> consider;
  thread_local std::vector<float> key_lo;
  far_list.clear();
  consider.assign(lights, 0);
  key_lo.assign(lights, 0.0f);
  bool any_near = false;
  float near_key_hi = -1;  // the largest sort key a near emitter can have at a receiver
  const bool per_object = settings_.blocking == SlBlocking::kPerObject;
  for (std::size_t i = 0; i < lights; ++i) {
    const SphereLightSource<N>& l = lights_[i];
    if (!(l.radius > 0)) continue;
    const glm::vec3 to = l.centre - centre;
    const float d = glm::length(to);
    // Culled at every receiver: wholly below all their planes, or smaller than min_sin.
    const bool outside = d > radius + l.radius;
    const bool below =
        glm::dot(normal, to) + l.radius + level.thickness[k] + level.spread[k] * (d + radius) <= 0;
    const bool small = min_sin > 0 && outside && l.radius <= min_sin * (d - radius);
    if (outside && (below || small)) {
      far[i] = 1;  // nothing to shade anywhere in the cluster, and no view to block with
      continue;
    }
    // Its sort key's range over the cluster (front to back: the object's centre distance for
    // kPerObject, else the SL's).
    const float key = per_object ? glm::length(object_centres_[l.object] - centre) : d;
    key_lo[i] = key - radius;
    consider[i] = 1;
    if (!emits_[i]) continue;  // a blocker only
    if (shrunk[i].far && ratio[i].x >= 0) {
      far_list.push_back({shrunk[i].centre, shrunk[i].radius * shrunk[i].radius,
                          shrunk[i].plane_weight * ratio[i], l.object});
    } else {
      far[i] = 0;  // not seen at the centre (min_sin) or not far: exact at every receiver
      any_near = true;
      near_key_hi = std::max(near_key_hi, key + radius);
    }
  }
  // The cap integral of a far term at (p, n): pi sin^2 cos beta x the min_sin fade, as the
  // lanes below compute it.
  constexpr float kPi = 3.14159265358979f;
  const auto far_cap = [min_sin](const glm::vec3& c, float r2, const glm::vec3& p,
                                 const glm::vec3& n) {
    const glm::vec3 t = c - p;
    const float inv_d = 1.0f / std::sqrt(glm::dot(t, t));
    const float s2 = r2 * inv_d * inv_d;
    float v = kPi * s2 * glm::dot(n, t) * inv_d;
    if (min_sin > 0) {
      const float f = std::clamp((std::sqrt(s2) - min_sin) / min_sin, 0.0f, 1.0f);
      v *= f * f * (3 - 2 * f);
    }
    return v;
  };
  std::size_t parents = 0;
  if (clusters.settings.hierarchy == SlHierarchy::kParents && far_list.size() > 1) {
    // [Guerrero08] eq. 25-26 (header): an object's far SLs become their bounding parent when it
    // is far and wholly above every receiver's plane; t = sum of the children's L~ V~ over the
    // parent's cap integral, both at the centre.
    std::stable_sort(far_list.begin(), far_list.end(),
                     [](const Far& a, const Far& b) { return a.object < b.object; });
    std::size_t kept = 0;
    for (std::size_t a = 0; a < far_list.size();) {
      std::size_t b = a + 1;
      while (b < far_list.size() && far_list[b].object == far_list[a].object) ++b;
      bool merged = false;
      if (b - a > 1) {
        glm::vec3 c(0.0f);
        float weight = 0;
        for (std::size_t i = a; i < b; ++i)
          c += far_list[i].r2 * far_list[i].centre, weight += far_list[i].r2;
        c /= weight;
        float r = 0;
        for (std::size_t i = a; i < b; ++i)
          r = std::max(r, glm::length(far_list[i].centre - c) + std::sqrt(far_list[i].r2));
        const float d = glm::length(c - centre);
        const float vary = level.thickness[k] + level.spread[k] * (d + radius);
        const bool far_parent = d > r && radius <= clusters.settings.far_ratio * (d - r) &&
                                glm::dot(normal, c - centre) - r >= vary;
        const float parent_cap = far_parent ? far_cap(c, r * r, centre, normal) : 0.0f;
        if (parent_cap > 0) {
          glm::vec3 children(0.0f);
          for (std::size_t i = a; i < b; ++i)
            children +=
                far_cap(far_list[i].centre, far_list[i].r2, centre, normal) * far_list[i].ratio;
          far_list[kept++] = {c, r * r, children / parent_cap, far_list[a].object};
          ++parents;
          merged = true;
        }
      }
      if (!merged)
        for (std::size_t i = a; i < b; ++i) far_list[kept++] = far_list[i];
      a = b;
    }
    far_list.resize(kept);
  }
  // The per-receiver path needs the near emitters and what can sort in front of one of them;
  // SLs behind every near emitter at every receiver change nothing there (header: ours).
  for (std::size_t i = 0; i < lights; ++i)
    if (consider[i] && far[i] && !(key_lo[i] < near_key_hi)) consider[i] = 0;

  const std::uint32_t m = end - begin,
                      m8 = (m + sh::kLaneCount - 1) / sh::kLaneCount * sh::kLaneCount;
  thread_local std::vector<float> soa;
  soa.assign(9 * static_cast<std::size_t>(m8), 0.0f);
  float *px = soa.data(), *py = px + m8, *pz = py + m8, *nx = pz + m8, *ny = nx + m8, *nz = ny + m8,
        *ex = nz + m8, *ey = ex + m8, *ez = ey + m8;
  for (std::uint32_t j = 0; j < m8; ++j) {
    // Padding lanes repeat the cluster's centre and normal; their results are dropped.
    const glm::vec3 p = j < m ? clusters.points[begin + j] : centre;
    const glm::vec3 n = j < m ? clusters.normals[begin + j] : normal;
    px[j] = p.x, py[j] = p.y, pz[j] = p.z, nx[j] = n.x, ny[j] = n.y, nz[j] = n.z;
  }
  // Far SLs, 8 receivers at a time: pi sin^2 cos beta (the cap wholly above the plane,
  // cap_cosine_integral's first case) x the min_sin fade x the ratio.
  using sh::Lanes;
  for (std::uint32_t j = 0; j < m8 && !far_list.empty(); j += sh::kLaneCount) {
    const Lanes x = sh::load_lanes(px + j), y = sh::load_lanes(py + j), z = sh::load_lanes(pz + j);
    const Lanes u = sh::load_lanes(nx + j), v = sh::load_lanes(ny + j), w = sh::load_lanes(nz + j);
    Lanes sx = sh::splat(0), sy = sh::splat(0), sz = sh::splat(0);
    for (const Far& f : far_list) {
      const Lanes tx = sh::splat(f.centre.x) - x, ty = sh::splat(f.centre.y) - y,
                  tz = sh::splat(f.centre.z) - z;
      const Lanes d2 = tx * tx + ty * ty + tz * tz;
      const Lanes inv_d = sh::splat(1.0f) / sh::lane_sqrt(d2);
      const Lanes s2 = sh::splat(f.r2) * inv_d * inv_d;
      Lanes c = sh::splat(kPi) * s2 * (u * tx + v * ty + w * tz) * inv_d;
      if (min_sin > 0) {
        const Lanes t =
            sh::lane_clamp01((sh::lane_sqrt(s2) - sh::splat(min_sin)) * sh::splat(1 / min_sin));
        c = c * t * t * (sh::splat(3) - sh::splat(2) * t);
      }
      sx += c * f.ratio.x, sy += c * f.ratio.y, sz += c * f.ratio.z;
    }
    sh::store_lanes(sx, ex + j), sh::store_lanes(sy, ey + j), sh::store_lanes(sz, ez + j);
  }
  if (counts) counts->far += m * far_list.size(), counts->parents += m * parents;
  if (any_near && settings_.horizon == EmitterHorizon::kClip) {
    for (std::uint32_t j = 0; j < m; ++j) {
      const glm::vec3 e = evaluate(clusters.points[begin + j], clusters.normals[begin + j], counts,
                                   far.data(), nullptr, min_sin, consider.data());
      ex[j] += e.x, ey[j] += e.y, ez[j] += e.z;
    }
  } else if (any_near) {
    // The per-receiver path (kShrink): the views and emitter terms 8 receivers a lane step
    // (view_lanes), then per receiver the sort, the overlap tests and the exponentials.
    thread_local std::vector<std::uint32_t> near_lights;
    thread_local std::vector<float> lanes;
    thread_local std::vector<View> views;
    near_lights.clear();
    for (std::uint32_t o = 0; o + 1 < object_first_.size(); ++o)  // evaluate()'s order
      for (std::uint32_t q = object_first_[o]; q < object_first_[o + 1]; ++q)
        if (consider[object_lights_[q]]) near_lights.push_back(object_lights_[q]);
    const std::size_t nl = near_lights.size();
    lanes.resize(nl * kLaneFields * sh::kLaneCount);
    views.resize(std::max<std::size_t>(nl, 1));
    for (std::uint32_t j0 = 0; j0 < m; j0 += sh::kLaneCount) {
      const float* const receiver[6] = {px + j0, py + j0, pz + j0, nx + j0, ny + j0, nz + j0};
      view_lanes(receiver, near_lights, far.data(), lanes.data());
      for (std::uint32_t j = j0; j < std::min(m, j0 + sh::kLaneCount); ++j) {
        const std::uint32_t lane = j - j0;
        int count = 0;
        for (std::size_t q = 0; q < nl; ++q) {
          const float* f = lanes.data() + q * kLaneFields * sh::kLaneCount + lane;
          constexpr int W = sh::kLaneCount;
          if (!(f[4 * W] > 0)) continue;
          blocker_accumulation::BlockerView bv;
          bv.axis = glm::vec3(f[0], f[W], f[2 * W]);
          bv.sin_angle = f[3 * W];
          bv.weight = f[4 * W];
          const std::uint32_t i = near_lights[q];
          const bool ready = emits_[i] && !far[i];
          views[count++] = {
              bv,        bv,
              f[5 * W],  f[5 * W],
              -1.0f,     f[6 * W],
              f[7 * W],  i,
              ready,     ready ? glm::vec3(f[8 * W], f[9 * W], f[10 * W]) : glm::vec3(0.0f),
              f[11 * W], f[12 * W]};
        }
        const glm::vec3 n(nx[j], ny[j], nz[j]);
        if (counts) {  // what evaluate() would have looked at (its objects' bound)
          const glm::vec3 p(px[j], py[j], pz[j]);
          for (std::uint32_t o = 0; o + 1 < object_first_.size(); ++o) {
            const glm::vec3 to_bound = object_centres_[o] - p;
            const float bound_d2 = glm::dot(to_bound, to_bound), bound_r = object_radius_[o];
            if (bound_d2 > bound_r * bound_r &&
                (glm::dot(n, to_bound) + bound_r <= 0 ||
                 (min_sin > 0 && bound_r * bound_r <= min_sin * min_sin * bound_d2)))
              continue;
            for (std::uint32_t q = object_first_[o]; q < object_first_[o + 1]; ++q)
              counts->lights += consider[object_lights_[q]];
          }
        }
        const glm::vec3 e = shade_views(n, views.data(), count, counts, far.data(), nullptr);
        ex[j] += e.x, ey[j] += e.y, ez[j] += e.z;
      }
    }
  }
  for (std::uint32_t j = 0; j < m; ++j)
    out[clusters.order[begin + j]] = glm::vec3(ex[j], ey[j], ez[j]);
}

template <int N>
void SphereLightGather<N>::shade(const SlReceiverClusters& clusters,
                                 std::span<glm::vec3> irradiance_out, Counts* counts) const {
  if (irradiance_out.size() != clusters.order.size()) {
    throw std::invalid_argument("SphereLightGather::shade: output and clusters differ in size");
  }
  const std::size_t count = clusters.size();
  if (counts) {
    for (std::size_t k = 0; k < count; ++k) shade_coarse(clusters, k, irradiance_out, counts);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k)
                        shade_coarse(clusters, k, irradiance_out, nullptr);
                    });
}

template class SphereLightGather<3>;
template class SphereLightGather<4>;
template class SphereLightGather<5>;

}  // namespace penumbra::spherical_lights
