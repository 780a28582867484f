// The log-SH visibility sum at one receiver over many sphere blockers, eight blockers per step on
// vector lanes: view_blocker's plane rule and add_log_visibility's cap ([Giraud] eq. 24-26, the
// eps cap), lane by lane (sphere_blocker.h states the rule). BlockerAccumulation and
// ReceiverClusters feed it every blocker a receiver sees; it is the inner loop of both.
// Same results as view_blocker + add_log_visibility per blocker up to float rounding (the lanes
// sum in another order): tests/blocker_accumulation/blocker_log_sum_test.cpp.
// Threading: one object per receiver and thread (it lives on the stack).
#pragma once

#include <cstddef>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/lanes.h"
#include "penumbra/systems/blocker_accumulation/sphere_blocker.h"

namespace penumbra::blocker_accumulation {

template <int N>
class BlockerLogSum {
 public:
  // Steps of eight blockers whose axes the depth limit looks at (blocker_accumulation.h): the
  // first kMaxSteps steps with a blocker of weight > 0; later ones are not looked at.
  static constexpr int kMaxSteps = 16;

  // Receiver p with unit normal n; log_eps = log(settings.epsilon).
  BlockerLogSum(const glm::vec3& p, const glm::vec3& n, const SphereBlockerSettings& settings,
                float log_eps);
  // Seen from a point with no tangent plane of its own (a cluster centre, receiver_clusters.h):
  // each sphere as view_blocker sees it with the normal pointing at the sphere's centre, so the
  // plane rule leaves it whole (weight 1) unless it contains the point.
  BlockerLogSum(const glm::vec3& p, const SphereBlockerSettings& settings, float log_eps);

  // The sphere (centre, radius) as a blocker, its log-SH scaled by `scale` (>= 0: the
  // hierarchy's blend and coverage). Buffered; every eighth call runs the lanes.
  void add(const glm::vec3& centre, float radius, float scale) {
    cx_[pending_] = centre.x;
    cy_[pending_] = centre.y;
    cz_[pending_] = centre.z;
    radius_[pending_] = radius;
    scale_[pending_] = scale;
    if (++pending_ == sh::kLaneCount) flush();
  }
  // Runs what is buffered and adds the whole sum to `sum`. Call once, after the last add.
  void finish(sh::Coeffs<N>& sum);

  std::size_t views() const { return views_; }  // spheres added
  std::size_t adds() const { return adds_; }    // of those, with weight > 0
  float weight() const { return weight_; }      // summed weights (log eps units; after finish)
  // The lowest value `sum` takes at the axes of the blockers with weight > 0 (the deepest point
  // of a log-visibility, which is <= 0 there), from the basis the caps were built with; 0 when
  // there is none. For the depth limit.
  float lowest_at_axes(const sh::Coeffs<N>& sum) const;
  int axis_steps() const { return steps_; }       // steps kept for lowest_at_axes
  int axis_count() const { return axis_count_; }  // axes in them (blockers with weight > 0)

 private:
  void flush();

  glm::vec3 p_, n_;
  bool towards_centre_ = false;     // the normal of each lane points at its sphere
  SphereBlockerSettings settings_;  // a copy: the caller's may be a temporary
  float log_eps_;
  int pending_ = 0;
  alignas(32) float cx_[sh::kLaneCount], cy_[sh::kLaneCount], cz_[sh::kLaneCount];
  alignas(32) float radius_[sh::kLaneCount], scale_[sh::kLaneCount];
  sh::Lanes acc_[N * N];  // per lane, that lane's blockers' sum
  sh::Lanes weight_lanes_;
  float weight_ = 0;
  std::size_t views_ = 0, adds_ = 0;
  sh::Lanes basis_[kMaxSteps][N * N];  // per kept step, y_i at its lanes' axes
  unsigned used_[kMaxSteps];           // per kept step, the lanes with weight > 0
  int steps_ = 0;
  int axis_count_ = 0;
};

}  // namespace penumbra::blocker_accumulation
