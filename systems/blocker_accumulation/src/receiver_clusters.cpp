#include "penumbra/systems/blocker_accumulation/receiver_clusters.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
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

ReceiverClusterCounts& operator+=(ReceiverClusterCounts& a, const ReceiverClusterCounts& b) {
  a.clusters += b.clusters;
  a.receivers += b.receivers;
  a.receiver_views += b.receiver_views;
  a.receiver_adds += b.receiver_adds;
  a.centre_views += b.centre_views;
  a.centre_adds += b.centre_adds;
  a.far_groups += b.far_groups;
  a.near_groups += b.near_groups;
  a.near_by_plane += b.near_by_plane;
  a.shared_receivers += b.shared_receivers;
  a.depth_evaluations += b.depth_evaluations;
  return a;
}

constexpr int kMaxFarAxes = 64;

}  // namespace

template <int N>
ReceiverClusters<N>::ReceiverClusters(const ReceiverClusterSettings& settings)
    : settings_(settings) {
  if (settings.max_receivers == 0)
    throw std::invalid_argument("receiver clusters: max_receivers must be at least 1");
  if (!(settings.far_sin >= 0 && settings.far_sin < 1) || !(settings.far_error >= 0))
    throw std::invalid_argument("receiver clusters: far_sin must be in [0, 1), far_error >= 0");
}

template <int N>
void ReceiverClusters<N>::set_receivers(std::span<const glm::vec3> points,
                                        std::span<const glm::vec3> normals) {
  if (points.empty()) throw std::invalid_argument("receiver clusters: no receivers");
  if (normals.size() != points.size())
    throw std::invalid_argument("receiver clusters: " + std::to_string(points.size()) +
                                " points but " + std::to_string(normals.size()) + " normals");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!finite(points[i]) || !finite(normals[i]))
      throw std::invalid_argument("receiver " + std::to_string(i) + ": point " + str(points[i]) +
                                  " or normal " + str(normals[i]) + " is not finite");
  std::vector<std::uint32_t> order(points.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::vector<Cluster> clusters;
  // kd split: the median along the widest of the point and (scaled) normal extents.
  const auto split = [&](auto&& self, std::uint32_t b, std::uint32_t e) -> void {
    glm::vec3 plo(std::numeric_limits<float>::max()), phi(-std::numeric_limits<float>::max());
    glm::vec3 nlo = plo, nhi = phi;
    for (std::uint32_t k = b; k < e; ++k) {
      plo = glm::min(plo, points[order[k]]);
      phi = glm::max(phi, points[order[k]]);
      nlo = glm::min(nlo, normals[order[k]]);
      nhi = glm::max(nhi, normals[order[k]]);
    }
    if (e - b <= settings_.max_receivers) {
      Cluster c;
      c.first = b;
      c.count = e - b;
      c.centre = 0.5f * (plo + phi);
      glm::vec3 mean(0.0f);
      for (std::uint32_t k = b; k < e; ++k) {
        c.radius = std::max(c.radius, glm::length(points[order[k]] - c.centre));
        mean += normals[order[k]];
      }
      const float len = glm::length(mean);
      c.cos_cone = -1;  // no usable mean: any normal
      if (len > 1e-6f * static_cast<float>(e - b)) {
        c.normal = mean / len;
        c.cos_cone = 1;
        for (std::uint32_t k = b; k < e; ++k)
          c.cos_cone = std::min(c.cos_cone, glm::dot(normals[order[k]], c.normal));
      }
      c.h_min = std::numeric_limits<float>::max();
      c.h_max = -std::numeric_limits<float>::max();
      for (std::uint32_t k = b; k < e; ++k) {
        const float h = glm::dot(normals[order[k]], points[order[k]] - c.centre);
        c.h_min = std::min(c.h_min, h);
        c.h_max = std::max(c.h_max, h);
      }
      clusters.push_back(c);
      return;
    }
    const glm::vec3 pe = phi - plo;
    const float scale = 0.5f * std::max({pe.x, pe.y, pe.z});
    const glm::vec3 ne = (nhi - nlo) * scale;
    int axis = 0;
    float widest = -1;
    for (int a = 0; a < 6; ++a) {
      const float w = a < 3 ? pe[a] : ne[a - 3];
      if (w > widest) widest = w, axis = a;
    }
    const auto key = [&](std::uint32_t i) {
      return axis < 3 ? points[i][axis] : normals[i][axis - 3];
    };
    const std::uint32_t mid = b + (e - b) / 2;
    std::nth_element(order.begin() + b, order.begin() + mid, order.begin() + e,
                     [&](std::uint32_t x, std::uint32_t y) { return key(x) < key(y); });
    self(self, b, mid);
    self(self, mid, e);
  };
  split(split, 0, static_cast<std::uint32_t>(order.size()));
  points_.resize(order.size());
  normals_.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    points_[k] = points[order[k]];
    normals_[k] = normals[order[k]];
  }
  order_ = std::move(order);
  clusters_ = std::move(clusters);
}

template <int N>
void ReceiverClusters<N>::shade(const BlockerAccumulation<N>& acc, const sh::CoeffsRgb<N>& radiance,
                                std::span<glm::vec3> irradiance,
                                std::span<sh::Coeffs<N>> visibility,
                                ReceiverClusterCounts* counts) const {
  if (irradiance.size() != points_.size() ||
      (!visibility.empty() && visibility.size() != points_.size()))
    throw std::invalid_argument("receiver clusters shade: " + std::to_string(points_.size()) +
                                " receivers but outputs of " + std::to_string(irradiance.size()) +
                                " and " + std::to_string(visibility.size()));
  const BlockerSettings& set = acc.settings_;
  const float log_eps = acc.log_eps_, cut_sin = acc.cut_sin_;
  const float min_sin = set.blocker.min_sin, max_depth = set.blocker.max_depth;
  const bool cut = set.hierarchy == BlockerHierarchy::kObjects;
  const bool product_path = set.shading == BlockerShading::kProduct && acc.lights_.empty();
  SphereBlockerSettings unfaded = set.blocker;  // the ratio's views: geometry only
  unfaded.min_sin = 0;
  tbb::combinable<ReceiverClusterCounts> tally;

  const auto shade_cluster = [&](const Cluster& cl, ReceiverClusterCounts& cnt) {
    struct Near {
      std::uint32_t group;
      bool has_ratio;
      std::array<float, N> ratio;  // per band, the bound's scale ([Guerrero08] eq. 25)
    };
    std::vector<Near> near;
    sh::Coeffs<N> far{};
    std::array<sh::Coeffs<N>, 3> far_gradient{};  // d far / d x, y, z (far_gradient setting)
    std::vector<std::uint32_t> far_spheres;
    float far_weight = 0;
    int far_axes = 0;
    // y_i at each far group's axis, eight axes per step (lane l of step k: axis 8 k + l).
    sh::Lanes far_basis[kMaxFarAxes / sh::kLaneCount][N * N];
    const auto add_far_axis = [&](const glm::vec3& axis) {
      if (far_axes >= kMaxFarAxes) return;
      float y[N * N];
      sh::eval_basis<N>(axis, y);
      const int step = far_axes / sh::kLaneCount, lane = far_axes % sh::kLaneCount;
      if (lane == 0)
        for (sh::Lanes& b : far_basis[step]) b = sh::Lanes{};
      for (int i = 0; i < N * N; ++i) far_basis[step][i][lane] = y[i];
      ++far_axes;
    };
    // The normal cone's half-angle alpha, as its cosine and sine.
    const float cos_a = std::clamp(cl.cos_cone, -1.0f, 1.0f);
    const float sin_a = std::sqrt(std::max(0.0f, 1 - cos_a * cos_a));
    // The view of sphere s from the centre with the plane rule neutral (normal towards s: the
    // sphere is then wholly above the plane, weight 1), as at every receiver of a far group.
    const auto centre_view = [&](const WorldSphere& s, const SphereBlockerSettings& bs) {
      const glm::vec3 to = s.centre - cl.centre;
      const float d = glm::length(to);
      ++cnt.centre_views;
      return view_blocker(cl.centre, d > 0 ? to / d : glm::vec3(0, 0, 1), s.centre, s.radius, bs);
    };
    // The eps cap: the far spheres eight per step (blocker_log_sum.h), seen from x_C.
    const bool use_lanes = !acc.clipped_log_;
    BlockerLogSum<N> far_lanes(cl.centre, set.blocker, log_eps);
    for (std::uint32_t gi = 0; gi < acc.groups_.size(); ++gi) {
      const BlockerGroup& g = acc.groups_[gi];
      const float r = g.bound.radius;
      if (!(r > 0)) continue;
      const glm::vec3 to = g.bound.centre - cl.centre;
      const float d = glm::length(to);
      if (min_sin > 0 && d - cl.radius > influence_radius(r, min_sin)) continue;  // out of reach
      // Bounds on n_i . (c - p_i) = n_i . (c - x_C) - n_i . (p_i - x_C) over the cluster.
      // beta: the angle between the cone axis and the bound's direction. Over the cone the
      // normals make angles in [beta - alpha, beta + alpha] with it, clamped to [0, pi]:
      // cos(min(pi, beta + alpha)) and cos(max(0, beta - alpha)) without the trigonometry.
      const float cos_b = d > 0 ? std::clamp(glm::dot(to, cl.normal) / d, -1.0f, 1.0f) : 1.0f;
      const float sin_b = std::sqrt(std::max(0.0f, 1 - cos_b * cos_b));
      const float cos_far = cos_a < -cos_b ? -1.0f : cos_b * cos_a - sin_b * sin_a;
      const float cos_near = cos_b > cos_a ? 1.0f : cos_b * cos_a + sin_b * sin_a;
      const float lo = d * cos_far - cl.h_max;
      const float hi = d * cos_near - cl.h_min;
      if (hi + r <= 0) continue;  // below every receiver's tangent plane: culled everywhere
      const bool above = lo >= r;
      const float gap = d - cl.radius;  // nearest receiver to the bound's centre, at least
      const float s_max = gap > r ? r / gap : 1.0f;
      const bool small =
          s_max < settings_.far_sin && s_max * s_max * cl.radius < settings_.far_error * gap;
      if (small && above) {
        // [Ren06] / [Guerrero08] sec. 7.3: far from the whole cluster, summed once at x_C.
        ++cnt.far_groups;
        if (use_lanes) {  // the spheres' weights are summed by far_lanes; the group's axis here
          for (std::uint32_t k = g.first; k < g.first + g.count; ++k) {
            far_lanes.add(acc.spheres_[k].centre, acc.spheres_[k].radius, 1);
            far_spheres.push_back(k);
          }
          add_far_axis(to / d);
          continue;
        }
        float w = 0;
        glm::vec3 axis = to / d;
        for (std::uint32_t k = g.first; k < g.first + g.count; ++k) {
          const BlockerView v = centre_view(acc.spheres_[k], set.blocker);
          if (!(v.weight > 0)) continue;
          const float depth = acc.add_blocker_log(v, far);
          ++cnt.centre_adds;
          far_spheres.push_back(k);
          w += v.weight * depth;
          if (g.count == 1) axis = v.axis;
        }
        if (w > 0) {
          far_weight += w;
          add_far_axis(axis);
        }
        continue;
      }
      ++cnt.near_groups;
      if (small) ++cnt.near_by_plane;
      Near e{gi, false, {}};
      if (settings_.band_ratio && cut && g.count > 1 && d > r) {
        // Per band, the scale that best maps the bound's log-SH onto its spheres' at x_C.
        sh::Coeffs<N> bound{}, children{};
        acc.add_blocker_log(centre_view(g.bound, unfaded), bound);
        for (std::uint32_t k = g.first; k < g.first + g.count; ++k)
          acc.add_blocker_log(centre_view(acc.spheres_[k], unfaded), children);
        e.has_ratio = true;
        for (int l = 0; l < N; ++l) {
          double bb = 0, cb = 0;
          for (int m = -l; m <= l; ++m) {
            bb += double(bound[sh::index(l, m)]) * bound[sh::index(l, m)];
            cb += double(children[sh::index(l, m)]) * bound[sh::index(l, m)];
          }
          e.ratio[l] =
              bb > 1e-12 ? std::clamp(static_cast<float>(cb / bb), 0.0f, 4.0f) : g.coverage;
        }
      }
      near.push_back(e);
    }
    if (use_lanes) {
      far_lanes.finish(far);
      far_weight += far_lanes.weight();
      cnt.centre_views += far_lanes.views();
      cnt.centre_adds += far_lanes.adds();
    }
    const bool gradient = settings_.far_gradient && !far_spheres.empty() && cl.radius > 0;
    if (gradient) {
      // First-order parallax: forward differences of the far sum over half the cluster's radius.
      const float h = 0.5f * cl.radius;
      for (int a = 0; a < 3; ++a) {
        glm::vec3 x = cl.centre;
        x[a] += h;
        sh::Coeffs<N> at{};
        if (use_lanes) {
          BlockerLogSum<N> shifted(x, set.blocker, log_eps);
          for (const std::uint32_t k : far_spheres)
            shifted.add(acc.spheres_[k].centre, acc.spheres_[k].radius, 1);
          shifted.finish(at);
          cnt.centre_views += shifted.views();
        } else {
          for (const std::uint32_t k : far_spheres) {
            const WorldSphere& sp = acc.spheres_[k];
            ++cnt.centre_views;
            acc.add_blocker_log(
                view_blocker(x, glm::normalize(sp.centre - x), sp.centre, sp.radius, set.blocker),
                at);
          }
        }
        for (int i = 0; i < N * N; ++i) far_gradient[a][i] = (at[i] - far[i]) / h;
      }
    }
    // The lowest value of `sum` at the far groups' axes (eight per step).
    const auto lowest_at_far_axes = [&](const sh::Coeffs<N>& sum) {
      float lowest = 0;
      for (int k = 0; k * sh::kLaneCount < far_axes; ++k) {
        sh::Lanes v{};
        for (int i = 0; i < N * N; ++i) v += sum[i] * far_basis[k][i];
        alignas(32) float at[sh::kLaneCount];
        sh::store_lanes(v, at);
        for (int l = 0; l < sh::kLaneCount && k * sh::kLaneCount + l < far_axes; ++l)
          lowest = std::min(lowest, at[l]);
      }
      return lowest;
    };
    // Deepest the far sum reaches at its own axes (in log eps): a receiver whose near weight
    // cannot take that past max_depth skips evaluating its sum there.
    const float far_deepest = lowest_at_far_axes(far) / log_eps;
    constexpr int kMaxAxes = 64;  // scalar-path near axes per receiver the depth limit looks at
    // The depth limit of BlockerAccumulation::log_visibility over the far axes, the lane path's
    // near axes (`pairs`) and the scalar path's (`axes`).
    const auto depth_limit = [&](sh::Coeffs<N>& sum, float weight, float near_weight,
                                 const BlockerLogSum<N>* pairs, const glm::vec3* axes, int count) {
      if (!(max_depth > 0) || weight <= max_depth) return;
      float lowest = 0;
      const bool far_too = far_deepest + near_weight > max_depth;
      if (far_too) lowest = lowest_at_far_axes(sum);
      if (pairs) lowest = std::min(lowest, pairs->lowest_at_axes(sum));
      float at[kMaxAxes];  // the sum at each scalar-path axis, eight axes per step
      sh::evaluate_batch<N>(sum, std::span<const glm::vec3>(axes, static_cast<std::size_t>(count)),
                            std::span<float>(at, static_cast<std::size_t>(count)));
      for (int k = 0; k < count; ++k) lowest = std::min(lowest, at[k]);
      cnt.depth_evaluations += static_cast<std::size_t>((far_too ? far_axes : 0) + count +
                                                        (pairs ? pairs->axis_count() : 0));
      const float deepest = lowest / log_eps;
      if (deepest > max_depth) {
        const float scale = max_depth / deepest;
        for (float& x : sum) x *= scale;
      }
    };
    // The cluster's shared result (receivers with no near blocker).
    sh::Coeffs<N> far_limited = far;
    depth_limit(far_limited, far_weight, far_deepest + max_depth, nullptr, nullptr, 0);
    sh::Coeffs<N> far_visibility{};
    sh::CoeffsRgb<N> far_lit{};  // exp(far) * L per channel: E = far_lit . cosine lobe
    if (product_path) {
      far_visibility = sh::exp_visibility<N>(far_limited);
      for (int c = 0; c < 3; ++c) far_lit[c] = sh::product<N>(far_visibility, radiance[c]);
    }
    cnt.clusters += 1;
    cnt.receivers += cl.count;
    // kProduct receivers with a sum of their own: the exponential, product and dots run eight
    // receivers at a time on vector lanes (sh/batch.h; the same results as irradiance_from_log).
    sh::CoeffsBatch<N> pending;
    sh::DirBatch pending_normal;
    std::array<std::uint32_t, sh::kBatch> pending_out;
    int lanes = 0;
    const auto flush = [&] {
      if (lanes == 0) return;
      for (int l = lanes; l < sh::kBatch; ++l) {  // a partial batch: open-sky lanes
        pending.set(l, sh::Coeffs<N>{});
        pending_normal.set(l, glm::vec3(0, 0, 1));
      }
      sh::CoeffsBatch<N> v;
      sh::exp_visibility_batch<N>(pending, v);
      float e[3][sh::kBatch];
      sh::shade_zh_batch<N>(radiance, acc.clamped_cosine_, v, pending_normal, e);
      for (int l = 0; l < lanes; ++l) {
        irradiance[pending_out[l]] = glm::vec3(e[0][l], e[1][l], e[2][l]);
        if (!visibility.empty()) visibility[pending_out[l]] = v.get(l);
      }
      lanes = 0;
    };

    for (std::uint32_t k = cl.first; k < cl.first + cl.count; ++k) {
      const glm::vec3& p = points_[k];
      const glm::vec3& n = normals_[k];
      sh::Coeffs<N> sum{};
      float weight = 0;
      glm::vec3 axes[kMaxAxes];
      int axis_count = 0;
      std::size_t adds = 0;
      // The eps cap's blockers without a band ratio: eight per step (blocker_log_sum.h).
      BlockerLogSum<N> pairs(p, n, set.blocker, log_eps);
      const auto add = [&](const WorldSphere& s, float scale, const std::array<float, N>* ratio) {
        if (use_lanes && !ratio) {
          pairs.add(s.centre, s.radius, scale);
          return;
        }
        BlockerView v = view_blocker(p, n, s.centre, s.radius, set.blocker);
        ++cnt.receiver_views;
        v.weight *= scale;
        if (!(v.weight > 0)) return;
        float depth = 1;
        if (ratio) {
          sh::Coeffs<N> one{};
          depth = acc.add_blocker_log(v, one);
          for (int l = 0; l < N; ++l)
            for (int m = -l; m <= l; ++m)
              sum[sh::index(l, m)] += (*ratio)[l] * one[sh::index(l, m)];
          v.weight *= (*ratio)[0];
        } else {
          depth = acc.add_blocker_log(v, sum);
        }
        ++adds;
        weight += v.weight * depth;
        if (axis_count < kMaxAxes) axes[axis_count++] = v.axis;
      };
      for (const Near& e : near) {  // as BlockerAccumulation::accumulate
        const BlockerGroup& g = acc.groups_[e.group];
        if (g.count == 1) {
          add(acc.spheres_[g.first], 1.0f, nullptr);
          continue;
        }
        const float d = glm::length(g.bound.centre - p);
        const float s = d > g.bound.radius ? g.bound.radius / d : 1.0f;
        const float a = cut ? std::clamp((s - cut_sin) / (0.25f * cut_sin), 0.0f, 1.0f) : 1.0f;
        if (a < 1) {
          if (e.has_ratio)
            add(g.bound, 1 - a, &e.ratio);
          else
            add(g.bound, g.coverage * (1 - a), nullptr);
        }
        if (a > 0)
          for (std::uint32_t i = g.first; i < g.first + g.count; ++i)
            add(acc.spheres_[i], a, nullptr);
      }
      pairs.finish(sum);
      cnt.receiver_views += pairs.views();
      adds += pairs.adds();
      weight += pairs.weight();
      cnt.receiver_adds += adds;
      const std::uint32_t out = order_[k];
      sh::Coeffs<N>* vis = visibility.empty() ? nullptr : &visibility[out];
      if (adds == 0 && !gradient) {
        ++cnt.shared_receivers;
        if (product_path) {
          const sh::Coeffs<N> lobe = sh::rotate_zh<N>(acc.clamped_cosine_, n);
          irradiance[out] = glm::vec3(sh::dot<N>(far_lit[0], lobe), sh::dot<N>(far_lit[1], lobe),
                                      sh::dot<N>(far_lit[2], lobe));
          if (vis) *vis = far_visibility;
        } else {
          irradiance[out] = acc.irradiance_from_log(radiance, p, n, far_limited, vis);
        }
        continue;
      }
      for (int i = 0; i < N * N; ++i) sum[i] += far[i];
      if (gradient) {
        const glm::vec3 dp = p - cl.centre;
        for (int i = 0; i < N * N; ++i)
          sum[i] +=
              far_gradient[0][i] * dp.x + far_gradient[1][i] * dp.y + far_gradient[2][i] * dp.z;
      }
      depth_limit(sum, weight + far_weight, weight, &pairs, axes, axis_count);
      if (product_path) {
        pending.set(lanes, sum);
        pending_normal.set(lanes, n);
        pending_out[lanes] = out;
        if (++lanes == sh::kBatch) flush();
      } else {
        irradiance[out] = acc.irradiance_from_log(radiance, p, n, sum, vis);
      }
    }
    flush();
  };

  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, clusters_.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      ReceiverClusterCounts& cnt = tally.local();
                      for (std::size_t c = range.begin(); c != range.end(); ++c)
                        shade_cluster(clusters_[c], cnt);
                    });
  if (counts) tally.combine_each([&](const ReceiverClusterCounts& c) { *counts += c; });
}

template class ReceiverClusters<3>;
template class ReceiverClusters<4>;
template class ReceiverClusters<5>;
template class ReceiverClusters<6>;

}  // namespace penumbra::blocker_accumulation
