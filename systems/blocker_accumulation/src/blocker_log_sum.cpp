#include "penumbra/systems/blocker_accumulation/blocker_log_sum.h"

#include <algorithm>

namespace penumbra::blocker_accumulation {
namespace {
using sh::Lanes;

Lanes smoothstep01_lanes(Lanes x) {
  x = sh::lane_clamp01(x);
  return x * x * (3.0f - 2.0f * x);
}
}  // namespace

template <int N>
BlockerLogSum<N>::BlockerLogSum(const glm::vec3& p, const glm::vec3& n,
                                const SphereBlockerSettings& settings, float log_eps)
    : p_(p), n_(n), settings_(settings), log_eps_(log_eps) {
  for (Lanes& a : acc_) a = Lanes{};
  weight_lanes_ = Lanes{};
}

template <int N>
BlockerLogSum<N>::BlockerLogSum(const glm::vec3& p, const SphereBlockerSettings& settings,
                                float log_eps)
    : BlockerLogSum(p, glm::vec3(0, 0, 1), settings, log_eps) {
  towards_centre_ = true;
}

template <int N>
void BlockerLogSum<N>::flush() {
  if (pending_ == 0) return;
  for (int l = pending_; l < sh::kLaneCount; ++l) {  // a partial step: empty lanes
    cx_[l] = p_.x;
    cy_[l] = p_.y;
    cz_[l] = p_.z;
    radius_[l] = 0;
    scale_[l] = 0;
  }
  views_ += static_cast<std::size_t>(pending_);
  pending_ = 0;
  // view_blocker (sphere_blocker.cpp), lane by lane: the plane rule of [Guerrero08] sec. 6.2.
  const Lanes r = sh::load_lanes(radius_);
  const Lanes cx = sh::load_lanes(cx_), cy = sh::load_lanes(cy_), cz = sh::load_lanes(cz_);
  Lanes nx = sh::splat(n_.x), ny = sh::splat(n_.y), nz = sh::splat(n_.z);
  if (towards_centre_) {  // n = (c - p) / |c - p|, (0, 0, 1) for a sphere centred on p
    const Lanes dx = cx - p_.x, dy = cy - p_.y, dz = cz - p_.z;
    const Lanes len = sh::lane_sqrt(dx * dx + dy * dy + dz * dz);
    const sh::LaneMask apart = len > 0.0f;
    const Lanes inv = 1.0f / sh::select(apart, len, sh::splat(1.0f));
    nx = sh::select(apart, dx * inv, Lanes{});
    ny = sh::select(apart, dy * inv, Lanes{});
    nz = sh::select(apart, dz * inv, sh::splat(1.0f));
  }
  const Lanes t = nx * (cx - p_.x) + ny * (cy - p_.y) + nz * (cz - p_.z) + r;
  const Lanes r1 = sh::lane_min(r, 0.5f * t);
  const Lanes shift = r - r1;
  const Lanes tx = cx + shift * nx - p_.x, ty = cy + shift * ny - p_.y, tz = cz + shift * nz - p_.z;
  const Lanes d = sh::lane_sqrt(tx * tx + ty * ty + tz * tz);
  const sh::LaneMask valid = (r > 0.0f) & (t > 0.0f) & (d > 0.0f);
  const Lanes safe_d = sh::select(valid, d, sh::splat(1.0f));
  const Lanes inv_d = 1.0f / safe_d;
  const Lanes ax = tx * inv_d, ay = ty * inv_d, az = tz * inv_d;
  const Lanes sin_angle = sh::lane_min(r1 * inv_d, sh::splat(1.0f));  // [Giraud] eq. 24, guarded
  Lanes w = smoothstep01_lanes(t * (0.5f / sh::select(valid, r, sh::splat(1.0f))));
  if (settings_.min_sin > 0)
    w *= smoothstep01_lanes((sin_angle - settings_.min_sin) * (1.0f / settings_.min_sin));
  if (settings_.ratio == RatioAttenuation::kOn) w *= sin_angle;  // [Giraud] sec. 4.2
  w = sh::select(valid, w * sh::load_lanes(scale_), Lanes{});
  w = sh::select(w > 0.0f, w, Lanes{});
  const Lanes cos_angle = sh::lane_sqrt(1.0f - sin_angle * sin_angle);
  const unsigned used = sh::lane_bits(w > 0.0f);
  adds_ += static_cast<std::size_t>(__builtin_popcount(used));
  weight_lanes_ += w;
  const bool keep = used != 0 && steps_ < kMaxSteps;               // its axes, for the depth limit
  sh::add_cap_lanes<N>(ax, ay, az, cos_angle, w * log_eps_, acc_,  // [Giraud] eq. 26
                       keep ? basis_[steps_] : nullptr);
  if (keep) {
    used_[steps_++] = used;
    axis_count_ += __builtin_popcount(used);
  }
}

template <int N>
float BlockerLogSum<N>::lowest_at_axes(const sh::Coeffs<N>& sum) const {
  float lowest = 0;
  for (int k = 0; k < steps_; ++k) {
    Lanes v{};
    for (int i = 0; i < N * N; ++i) v += sum[i] * basis_[k][i];
    alignas(32) float at[sh::kLaneCount];
    sh::store_lanes(v, at);
    for (int l = 0; l < sh::kLaneCount; ++l)
      if ((used_[k] >> l) & 1) lowest = std::min(lowest, at[l]);
  }
  return lowest;
}

template <int N>
void BlockerLogSum<N>::finish(sh::Coeffs<N>& sum) {
  flush();
  for (int i = 0; i < N * N; ++i) sum[i] += sh::lane_sum(acc_[i]);
  weight_ = sh::lane_sum(weight_lanes_);
}

template class BlockerLogSum<3>;
template class BlockerLogSum<4>;
template class BlockerLogSum<5>;
template class BlockerLogSum<6>;

}  // namespace penumbra::blocker_accumulation
