// One-bounce indirect light at receivers from spherical lights (SLs), each shadowed by the SLs in
// front of it ([Guerrero08] sec. 6-7). Usable without the ECS: give it world-space SLs with their
// radiance SH (reflector_lighting.h makes them from an object's sample points), then ask for any
// receivers. Local lights (uniform radiance, the terrain system's SphericalLight) are SLs too:
// the same code gives their direct light with the blockers' shadows ([Guerrero08] sec. 7.3).
//
// At a receiver p with unit normal n ([Guerrero08] eq. 14): E = sum_i L~_i V~_i, where
//  - every SL is first seen through the plane rule of the blocker system (sphere_blocker.h,
//    [Guerrero08] sec. 6.2 "receiver points inside SLs"): culled below the tangent plane,
//    shrunk above it, faded by its weight; SLs smaller than min_sin are skipped. As emitters,
//    SLs the receiver is outside of keep their whole sphere under EmitterHorizon::kClip (an
//    option; below);
//  - L~_i, the SL's average radiance towards p, is eq. 18 (sphere_light_tables.h);
//  - V~_i, its average visibility, is eq. 23-24: (exp(G_<i) - exp(G_<i + G_i)) . rho_n, G the
//    log-SH eps caps of the blockers in front (sphere_blocker.h, [Giraud] eq. 26).
// Which SLs are in front (SlBlocking, [Guerrero08] sec. 7.2, 8.3):
//  - kPerSphere: every SL nearer p (centre distance) than S_i, except the SLs of S_i's own object
//    that intersect it (their occlusion is in S_i's sample points, reflector_samples.h);
//  - kPerObject: objects ordered by their centres' distance; all SLs of nearer objects, then the
//    nearer non-intersecting SLs of S_i's own. Wrong where no order of whole objects exists
//    (interlocking or cyclic overlap, [Guerrero08] fig. 11): a test shows it.
// Ours, beyond [Guerrero08] (docs/spherical_lights.md measures each):
//  - only blockers whose cap overlaps S_i's cap enter G: the product of the others' indicators is
//    1 over S_i's cap, so dropping them is exact before band-limiting and removes their ringing
//    and their cost. A blocker's log is faded in over the last quarter of its angular radius of
//    overlap, so nothing pops when caps start to overlap;
//  - the visibility with nothing in front is the exact cosine-weighted solid angle of the cap
//    (cap_cosine_integral), and blockers subtract the SH difference from it:
//    V~ = C_i + rho_n . [(exp(G) - exp(G + G_i)) - (1 - exp(G_i))] / (1 - eps),
//    which is eq. 23-24 for an SL with blockers, scaled by 1 / (1 - eps) because an eps cap
//    leaves eps of the light: (1 - eps^[cap]) = (1 - eps) [cap]. It is C_i when G = 0, so the
//    fade above is continuous, and the exponentials are only paid where caps overlap.
//  - a cap alone has its exponential from a table: exp of a zonal function is zonal and exp
//    commutes with rotation, so exp(G_i) (always one cap) and exp(G) with one blocker in front
//    are table rows (sin(angle) x weight, bilinear) dotted with the clamped cosine through
//    Legendre polynomials; only exp(G + G_i), and exp(G) with two or more blockers, are SH
//    exponentials;
//  - objects are culled whole first: when p is outside the sphere bounding an object's SLs and
//    that sphere is below p's tangent plane or smaller than min_sin, so is every SL in it (a
//    sphere inside another subtends a smaller angle from outside both): exact;
//  - overlap tests compare cosines (no acos); angles only for the overlapping pairs' fade;
//  - receiver clusters (shade(clusters), [Guerrero08] sec. 7.3 and its reflection ratio, eq.
//    25-26, in spirit): per planar cluster, an SL wholly above every receiver's plane and far
//    (cluster radius <= far_ratio x its distance) is evaluated once at the cluster's centre, as
//    the ratio L~ V~ / C of its light to its unblocked cap integral; each receiver multiplies
//    that ratio by its own exact C (and min_sin fade). The other SLs go through the per-receiver
//    path with the far ones still blocking. [Guerrero08] keeps V~ per receiver and swaps child
//    SLs for a parent; ours keeps the SLs and shares L~ and the visibility ratio, so a far SL
//    costs about 20 operations per receiver (8 receivers a lane step). Error: what L~ and the
//    ratio change across the cluster, bounded by far_ratio (docs/spherical_lights.md measures
//    it). Two levels: a coarse cluster with a near SL is shaded as its fine clusters (half the
//    cell), so the cut between far and near follows the distance to the objects. The
//    per-receiver path then looks only at the near emitters and the SLs that can sort in front
//    of one somewhere in the cluster (the others change nothing there: exact). Under kShrink its
//    views, eq. 18 and the unblocked cap integrals are taken 8 receivers a lane step; the sort,
//    the overlap tests and the exponentials stay per receiver.
//
// Errors: set_lights throws std::invalid_argument naming the light (index) with a non-finite
// centre or radiance, or a radius that is negative or not finite; a zero radius is no light.
// irradiance() names a non-finite point or normal.
// Threading: set_lights on one thread; the const members from any number of threads.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/zh.h"
#include "penumbra/systems/blocker_accumulation/sphere_blocker.h"
#include "penumbra/systems/spherical_lights/sphere_light_tables.h"

namespace penumbra::spherical_lights {

enum class SlBlocking { kPerSphere, kPerObject };

template <int N>
struct SphereLightSource {
  glm::vec3 centre{0.0f};  // world, metres
  float radius = 0;
  std::uint32_t object = 0;     // SLs of one object share it (order, intersections)
  glm::mat3 to_local{1.0f};     // world -> the frame of `radiance` (the object's inverse rotation)
  sh::CoeffsRgb<N> radiance{};  // L^c, W / (m^2 sr) per channel; all zero: blocks only
  bool blocks = true;           // false: emits only (a local light)
};

// How an emitting SL that crosses the receiver's tangent plane is seen:
//  - kShrink ([Guerrero08] sec. 6.2, after [Ren06]): like a blocker, by the plane rule (shrunk
//    above the plane and faded by its weight), so SLs at the horizon give too little light
//    ([Guerrero08] sec. 8.1: at 90 degrees a quarter of the exact value);
//  - kClip (ours): the whole sphere, its cap clipped by the horizon exactly in
//    cap_cosine_integral. The plane rule stays for receivers inside or touching an SL (distance
//    below its radius) and is blended out up to 1.25 radii, so nothing jumps; blockers always
//    take the plane rule. Exact for the ground around an object resting on it (the cube of
//    docs/spherical_light_accuracy.md: indirect bias -27% -> -3%), but receivers on an object's
//    own surface then see its neighbouring SLs whole, outside volume and all (the bench's
//    objects: 35% -> 48% RMS), and the clusters' far path takes only SLs wholly above the plane
//    (5x slower there). Hence not the default.
enum class EmitterHorizon { kShrink, kClip };

struct SphereLightSettings {
  SlBlocking blocking = SlBlocking::kPerSphere;
  // The blockers' eps, the plane rule's smallest SL (min_sin) and the rest (sphere_blocker.h).
  blocker_accumulation::SphereBlockerSettings blocker;
  EmitterHorizon horizon = EmitterHorizon::kShrink;
  // Eq. 16's weight (kCosine) or the exact solid angle (sphere_light_tables.h).
  AverageRadianceWeight radiance_weight = AverageRadianceWeight::kCosine;
  bool operator==(const SphereLightSettings&) const = default;
};

// Far SLs of one object in a cluster ([Guerrero08] sec. 7.3, eq. 25-26):
//  - kLeaves: each far SL is its own term at every receiver (its ratio at the cluster's centre
//    times the receiver's own cap integral);
//  - kParents: the far SLs of one object are replaced by their parent, the sphere bounding them,
//    when the parent is itself far and wholly above every receiver's plane; its reflection ratio
//    t = sum_j L~_j V~_j / C_parent at the cluster's centre (eq. 25, with the parent's unblocked
//    cap integral C as its diffuse reflection value) scales the parent's cap integral at each
//    receiver (eq. 26): one term per object instead of one per SL, exact at the centre.
enum class SlHierarchy { kLeaves, kParents };

// Receivers grouped once for SphereLightGather::shade(clusters) (header: ours, after
// [Guerrero08] sec. 7.3): binned by a cell of `cell` metres and the normal's dominant axis and
// sign, at most max_receivers each. A cluster is planar when its points lie in one plane and its
// normals within normal_cos of their mean (ground patches, mesh faces); only planar clusters
// take the far path. Fixed receivers (terrain texels) cluster once; receivers on a moving object
// cluster in its frame.
struct SlClusterSettings {
  float cell = 1.5f;
  int max_receivers = 256;
  // An SL is far when cluster radius <= far_ratio x (distance - radius). 0.5: the bench's
  // objects:64 frame in 28 ms against 35 ms at 0.25, 3.3% from the per-receiver result against
  // 1.5%, while the error against the reference moves from 34.9% to 35.1%
  // (docs/spherical_lights.md): the cheaper setting costs nothing the method's error shows.
  float far_ratio = 0.5f;
  float normal_cos = 0.99999f;  // planar: every normal within this cosine of the mean
  SlHierarchy hierarchy = SlHierarchy::kParents;
};

// One level of clusters: per cluster its receivers [first[k], first[k + 1]) of `order` and its
// geometry.
struct SlClusterLevel {
  std::vector<std::uint32_t> first;       // per cluster its first entry of `order`, then the end
  std::vector<glm::vec3> centre, normal;  // mean point, mean normal (unit)
  std::vector<float> radius;              // bounds its points around `centre`
  std::vector<float> thickness;           // max |normal . (p - centre)|
  std::vector<float> spread;              // max |n - normal| over its receivers
  std::vector<std::uint8_t> planar;
  std::size_t size() const { return first.empty() ? 0 : first.size() - 1; }
};

// Two levels: coarse cells of `cell` metres, each cut into fine cells of cell / 2 (at most
// max_receivers each). A coarse cluster with no near SL is shaded whole; otherwise its fine
// clusters are, each with its own far SLs ([Guerrero08] sec. 7.3's cut, by distance).
struct SlReceiverClusters {
  SlClusterSettings settings;
  std::vector<std::uint32_t> order;        // receiver indices, cluster by cluster
  std::vector<glm::vec3> points, normals;  // in `order` (normals unit)
  SlClusterLevel coarse, fine;
  std::vector<std::uint32_t> children;  // coarse k: fine clusters [children[k], children[k + 1])
  std::size_t size() const { return coarse.size(); }
};

// Errors: std::invalid_argument for sizes that differ, a non-finite point or normal (named by
// index), cell <= 0 or max_receivers < 1.
SlReceiverClusters cluster_receivers(std::span<const glm::vec3> points,
                                     std::span<const glm::vec3> normals,
                                     const SlClusterSettings& settings = {});

template <int N>
class SphereLightGather {
 public:
  explicit SphereLightGather(const SphereLightSettings& settings = {});

  const SphereLightSettings& settings() const { return settings_; }
  void set_lights(std::vector<SphereLightSource<N>> lights);
  std::span<const SphereLightSource<N>> lights() const { return lights_; }

  // What one receiver cost (benchmarks, tests).
  struct Counts {
    std::size_t views = 0;         // SLs past the plane rule and min_sin
    std::size_t emitters = 0;      // of those, shaded as lights
    std::size_t blocked = 0;       // emitters with a blocker in front (exponentials paid)
    std::size_t exponentials = 0;  // SH exponentials
    std::size_t lights = 0;        // SLs looked at (plane rule or bound)
    std::size_t pairs = 0;         // (emitter, SL in front) overlap tests
    std::size_t logs = 0;          // log-SH caps added (add_log_visibility)
    std::size_t far = 0;           // far terms shaded by their cluster's ratio (shade(clusters))
    std::size_t parents = 0;       // of those, parents standing for several far SLs (kParents)
  };
  // Irradiance (W/m^2 per channel) at p with unit normal n from every SL; `counts` gains the cost.
  glm::vec3 irradiance(const glm::vec3& p, const glm::vec3& n, Counts* counts = nullptr) const;
  void shade(std::span<const glm::vec3> points, std::span<const glm::vec3> normals,
             std::span<glm::vec3> irradiance) const;
  // Every receiver of `clusters`, irradiance[i] for receiver i (the original order): far SLs by
  // their ratio at the cluster's centre, the rest as irradiance(). Parallel over clusters in the
  // caller's TBB arena; sequential when `counts` is given.
  void shade(const SlReceiverClusters& clusters, std::span<glm::vec3> irradiance,
             Counts* counts = nullptr) const;

  const AverageRadianceTable<N>& table() const { return table_; }

 private:
  SphereLightSettings settings_;
  float log_eps_;
  AverageRadianceTable<N> table_;
  sh::Zonal<N> clamped_cosine_;
  std::vector<SphereLightSource<N>> lights_;
  std::vector<glm::vec3> object_centres_;  // per object id: the mean of its SLs' centres
  std::vector<std::uint8_t> emits_;        // per light: radiance not all zero
  // Per object id: a sphere around the mean bounding all its SLs, and its SLs' indices
  // [object_first_[o], object_first_[o + 1]) in object_lights_ (the bound's cull, header: ours).
  std::vector<float> object_radius_;
  std::vector<std::uint32_t> object_first_, object_lights_;
  // exp of one cap, zonal about +z, by sin(angle) (rows) and weight (columns); exp commutes with
  // rotation, so a lone cap's exponential is a rotated row (header: ours).
  static constexpr int kExpSin = 128, kExpWeight = 16;
  std::vector<sh::Zonal<N>> cap_exp_;  // (kExpSin + 1) x (kExpWeight + 1)
  sh::Zonal<N> cap_exp_zonal(float sin_angle, float weight) const;
  // irradiance() without the argument checks, at `min_sin`; only SLs with consider[i] set (all
  // when null) are looked at; SLs with skip[i] set are blockers only, and ratio_out[i] (when given)
  // receives L~ V~ / C of every SL seen as an emitter (0 when dark).
  glm::vec3 evaluate(const glm::vec3& p, const glm::vec3& n, Counts* counts,
                     const std::uint8_t* skip, glm::vec3* ratio_out, float min_sin,
                     const std::uint8_t* consider = nullptr) const;
  // evaluate()'s second half: the views sorted front to back, then eq. 14 over the emitters.
  struct View;
  glm::vec3 shade_views(const glm::vec3& n, View* views, int count, Counts* counts,
                        const std::uint8_t* skip, glm::vec3* ratio_out) const;
  // evaluate()'s first half for 8 receivers at once (kShrink): per SL of `lights`, kLaneFields
  // rows of 8 lanes (the view; for emitters not skipped, eq. 18 and the unblocked cap integral).
  static constexpr int kLaneFields = 13;
  void view_lanes(const float* const* receiver, std::span<const std::uint32_t> lights,
                  const std::uint8_t* skip, float* out) const;
  // A coarse cluster: whole when no SL is near, else its fine clusters one by one.
  void shade_coarse(const SlReceiverClusters& clusters, std::size_t k,
                    std::span<glm::vec3> irradiance, Counts* counts) const;
  bool has_near(const SlClusterLevel& level, std::size_t k, float far_ratio) const;
  void shade_cluster(const SlReceiverClusters& clusters, const SlClusterLevel& level, std::size_t k,
                     std::span<glm::vec3> irradiance, Counts* counts) const;
};

}  // namespace penumbra::spherical_lights
