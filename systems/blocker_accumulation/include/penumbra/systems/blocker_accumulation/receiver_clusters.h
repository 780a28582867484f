// Receiver clustering for the blocker accumulation ([Ren06], as used in [Guerrero08] sec. 7.3):
// receivers (points + normals) are grouped into spatial clusters once; each frame, per cluster,
// the blocker groups far from the whole cluster are summed ONCE at the cluster centre (a shared
// far-field log-SH vector), and only the near ones are evaluated per receiver. Usable without
// the ECS: give it the receivers, then shade them with any BlockerAccumulation.
//
// Clusters: a kd split (median along the widest of x, y, z and, scaled by half the node's
// widest extent, the normals' x, y, z) until a cluster holds at most max_receivers. Each cluster
// keeps its centre x_C (box centre), radius R (farthest receiver from x_C) and bounds on its
// normals (cone about the mean normal, range of n_i . (p_i - x_C)).
//
// Per cluster and frame, for every blocker group (bound (c, r), D = |c - x_C|):
//  - out of reach (D - R beyond the bound's influence radius, blocker_grid.h) or below every
//    receiver's tangent plane: skipped (exact: the per-receiver path gives it weight 0);
//  - far: its angular radius seen from anywhere in the cluster, s = r / (D - R), below far_sin
//    and s^2 R / (D - R) below far_error (ReceiverClusterSettings) AND
//    wholly above every receiver's tangent plane (n_i . (c - p_i) >= r for all i, from the
//    normal bounds): the plane rule of sphere_blocker.h then gives weight 1 at every receiver,
//    so the shared part does not depend on the normals. Its spheres (all of them, not the
//    bound) are summed at x_C;
//  - near: per receiver, as BlockerAccumulation::log_visibility does, except that a group's
//    bound standing for its spheres (hierarchy kObjects, beyond the cut) is scaled per band by
//    the ratio computed at x_C (least squares of the spheres' log-SH on the bound's, [Guerrero08]
//    eq. 25 in log-SH) instead of the disc coverage.
// A receiver then takes far + near, the depth limit (over the far groups' axes and its near
// blockers' axes) and one exponential. A receiver with no near blocker takes the cluster's
// shared result: with kProduct and no lights, W = exp(far) * L (SH products once per cluster),
// so its irradiance is W . (clamped cosine about n): no exponential per receiver. Same value as
// the full path up to rounding (the triple product is symmetric, all three band-limited).
//
// Errors: set_receivers throws std::invalid_argument for no receivers, points and normals of
// different sizes, a receiver (index) with a non-finite point or normal, or max_receivers 0
// (the constructor). shade throws std::invalid_argument on output sizes that differ from the
// receivers'.
// Measured speed-up, error against all pairs and seam jumps: docs/blocker_accumulation.md.
// Threading: set_receivers on one thread; shade (const) from any number of threads, each call
// runs tbb::parallel_for over the clusters in the caller's arena.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"

namespace penumbra::blocker_accumulation {

struct ReceiverClusterSettings {
  // Largest cluster: receivers are split until each cluster holds at most this many (a split
  // halves a node, so clusters hold between half and all of it).
  std::uint32_t max_receivers = 256;
  // A group is shared (summed at the cluster centre) when, with s = r / (D - R) the largest sin
  // of its bound's angular radius seen from anywhere in the cluster, s < far_sin and
  // s^2 R / (D - R) < far_error (the cap's solid angle times the parallax across the cluster:
  // the first-order change of its share of the irradiance, relative, over the cluster).
  float far_sin = 0.35f;
  float far_error = 0.005f;
  // Near groups whose bound stands for their spheres: the bound's log-SH scaled per band by the
  // ratio computed at the cluster centre (true), or by the disc coverage as the per-receiver
  // path does (false).
  bool band_ratio = true;
  // The shared sum with its first-order change over the cluster (forward differences at x_C +
  // R/2 along x, y, z, three more sums per cluster): each receiver takes far + G (p - x_C),
  // which removes most of the parallax error and the steps between clusters. Off: receivers
  // with no near blocker share the cluster's exponential and products.
  bool far_gradient = true;
  bool operator==(const ReceiverClusterSettings&) const = default;
};

// What a shade() call cost (for benchmarks and tests), summed over the receivers or clusters.
struct ReceiverClusterCounts {
  std::size_t clusters = 0;
  std::size_t receivers = 0;
  std::size_t receiver_views = 0;     // view_blocker calls at receivers (near groups)
  std::size_t receiver_adds = 0;      // log-SH vectors added at receivers
  std::size_t centre_views = 0;       // view_blocker calls at cluster centres (shared + ratios)
  std::size_t centre_adds = 0;        // log-SH vectors added at cluster centres
  std::size_t far_groups = 0;         // group-cluster pairs shared at the centre
  std::size_t near_groups = 0;        // group-cluster pairs evaluated per receiver
  std::size_t near_by_plane = 0;      // of those, far by size but crossing some tangent plane
  std::size_t shared_receivers = 0;   // receivers with no near blocker (the cluster's result)
  std::size_t depth_evaluations = 0;  // sum evaluations of the depth limit at receivers
};

template <int N>
class ReceiverClusters {
 public:
  struct Cluster {
    std::uint32_t first = 0, count = 0;  // receivers [first, first + count) of order()
    glm::vec3 centre{0.0f};
    float radius = 0;
    glm::vec3 normal{0.0f, 0.0f, 1.0f};  // cone axis (mean normal)
    float cos_cone = 1;                  // every normal n_i has n_i . normal >= cos_cone
    float h_min = 0, h_max = 0;          // range of n_i . (p_i - centre)
  };

  explicit ReceiverClusters(const ReceiverClusterSettings& settings = {});

  const ReceiverClusterSettings& settings() const { return settings_; }
  // Clusters the receivers (normals unit length). Throws as the header says.
  void set_receivers(std::span<const glm::vec3> points, std::span<const glm::vec3> normals);
  std::span<const Cluster> clusters() const { return clusters_; }
  // Receiver indices (into set_receivers' spans) in cluster order.
  std::span<const std::uint32_t> order() const { return order_; }

  // Irradiance (and, when `visibility` is not empty, the visibility SH) of every receiver, in
  // set_receivers' order, with the blockers, lights and settings of `blockers`. `counts`, when
  // given, gains what the call cost.
  void shade(const BlockerAccumulation<N>& blockers, const sh::CoeffsRgb<N>& radiance,
             std::span<glm::vec3> irradiance, std::span<sh::Coeffs<N>> visibility = {},
             ReceiverClusterCounts* counts = nullptr) const;

 private:
  ReceiverClusterSettings settings_;
  std::vector<glm::vec3> points_, normals_;  // in cluster order
  std::vector<std::uint32_t> order_;
  std::vector<Cluster> clusters_;
};

}  // namespace penumbra::blocker_accumulation
