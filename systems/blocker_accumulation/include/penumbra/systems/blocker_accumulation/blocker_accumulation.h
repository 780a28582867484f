// Soft shadows from dynamic sphere-set blockers: at each receiver the blockers' log-SH
// visibilities are summed and exponentiated once ([Giraud] sec. 4.2, [Guerrero08] eq. 6-8, on
// [Ren06]'s exponentials), then shaded with the environment's SH. Usable without the ECS: give
// it world-space spheres, then ask for any receivers.
//
// Shading (BlockerShading):
//  - kProduct ([Ren06]): V = exp(sum of log V_i); transfer T = V * max(0, n.w) as an SH product;
//    irradiance E = L . T.
//  - kLogBrdf ([Giraud] sec. 5, "Log-SH Diffuse"): the log-ZH of max(cos / pi, eps) about n is
//    added to the sum before the exponential, so no SH product is needed: E = pi L . exp(...).
// Exponentials are sh::exp_visibility (HYB, clamped to what a [0, 1] function can have).
//
// Many overlapping blockers ([Giraud] sec. 4.2: log eps summed m times): HYB's squarings
// diverge beyond about 4 coincident caps (the exponential then falls back to its clamp, which
// reads as no shadow at all). So before the exponential, when the blockers' summed weight
// exceeds max_depth, the sum is evaluated at each contributing blocker's axis (where caps are
// deepest) and, if deeper than max_depth log eps, scaled back to that depth: m coincident
// blockers shade like max_depth of them (eps^3 = 0.008 with the defaults), disjoint ones are
// untouched. tests/blocker_accumulation prints what this gives for 1 to 1,000 blockers.
//
// Errors: set_blockers throws std::invalid_argument naming the sphere (index) with a non-finite
// centre or a non-finite or negative radius; shade() names a receiver with a non-finite point
// or normal. A zero-radius sphere blocks nothing.
// Measured cost and accuracy: docs/blocker_accumulation.md.
// Threading: set_blockers on one thread; the const members from any number of threads.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"
#include "penumbra/sh/zh.h"
#include "penumbra/systems/blocker_accumulation/blocker_grid.h"
#include "penumbra/systems/blocker_accumulation/clipped_log_cap.h"
#include "penumbra/systems/blocker_accumulation/sphere_blocker.h"

namespace penumbra::blocker_accumulation {

enum class BlockerShading { kProduct, kLogBrdf };

// [Ren06] hierarchy, two levels: an object's spheres under one bounding sphere. A receiver that
// sees the bound smaller than the cut (angular radius 80 deg / N) takes the bound alone, its
// log-visibility scaled by `coverage` (the fraction of the bound's disc the spheres cover, seen
// from a distance), instead of every sphere of the object; over [cut, 1.25 cut] both, blended.
enum class BlockerHierarchy { kOff, kObjects };

struct BlockerGroup {
  WorldSphere bound;        // contains every sphere of the group
  std::uint32_t first = 0;  // the group's spheres: [first, first + count) of set_blockers'
  std::uint32_t count = 0;
  float coverage = 1;  // (0, 1]
};

// The group of `spheres` (an object's, in any frame) starting at index `first`: their bounding
// sphere and the fraction of the bound's disc they cover, averaged over the three axis
// projections on a 32 x 32 grid (at least 0.01). Empty input: a zero bound.
BlockerGroup bound_group(std::span<const WorldSphere> spheres, std::uint32_t first = 0);

// A local spherical light (uniform radiance over the sphere) the receivers see through the
// blockers: its cap, as SH radiance towards each receiver, joins the environment's radiance, so
// the same visibility (blockers and terrain) shadows it. Band-limited like everything here: a
// light small in the sky is blurred to the SH's resolution.
struct LightSource {
  glm::vec3 centre{0.0f};
  float radius = 0;
  glm::vec3 radiance{0.0f};
};

// A Phong lobe in log-SH ([Giraud] eq. 27): its exponent r, the floor eps of its log, and the
// canonical log-ZH about +z (rotated to the reflected view direction when shading).
template <int N>
struct PhongLobe {
  float exponent = 0;
  float epsilon = 0;
  sh::Zonal<N> log_zh{};
};

struct BlockerSettings {
  SphereBlockerSettings blocker;
  BlockerShading shading = BlockerShading::kProduct;
  // kLogBrdf: the floor of max(cos / pi, eps) before its log. The diffuse lobe peaks at
  // 1 / pi = 0.32, so the blockers' 0.2 would flatten most of it (docs/blocker_accumulation.md).
  float brdf_epsilon = 0.01f;
  // Phong exponent of glossy_radiance's lobe ([Giraud] eq. 27's r); 0: no glossy shading.
  float phong_exponent = 0;
  // The floor of that lobe's log; 0: fitted to the exponent (fitted_phong_epsilon).
  float phong_epsilon = 0;
  BlockerHierarchy hierarchy = BlockerHierarchy::kObjects;
  bool operator==(const BlockerSettings&) const = default;
};

template <int N>
class BlockerAccumulation {
 public:
  explicit BlockerAccumulation(const BlockerSettings& settings = {});

  const BlockerSettings& settings() const { return settings_; }
  // `groups` empty: every sphere is its own group. Otherwise they must cover the spheres in
  // order, without gaps (each group's bound is taken as given).
  void set_blockers(std::vector<WorldSphere> spheres, std::vector<BlockerGroup> groups = {});
  std::span<const WorldSphere> blockers() const { return spheres_; }
  std::span<const BlockerGroup> groups() const { return groups_; }  // cover blockers() in order
  // Local lights added to every receiver's radiance (throws std::invalid_argument naming a light
  // with a non-finite centre or radiance, or a negative radius). A receiver inside a light gets
  // nothing from it.
  void set_lights(std::vector<LightSource> lights);
  const BlockerGrid& grid() const { return grid_; }

  // What one receiver's sum cost (for benchmarks): blockers viewed (view_blocker calls), log-SH
  // vectors added, and evaluations of the sum by the depth limit.
  struct PairCounts {
    std::size_t views = 0, adds = 0, depth_evaluations = 0;
  };
  // Sum of the log-SH visibilities of every blocker that reaches (p, n), depth-limited;
  // `counts`, when given, gains what the sum cost.
  sh::Coeffs<N> log_visibility(const glm::vec3& p, const glm::vec3& n,
                               PairCounts* counts = nullptr) const;
  // The visibility itself: one exponential of that sum.
  sh::Coeffs<N> visibility(const glm::vec3& p, const glm::vec3& n) const;
  // Irradiance (per channel of `radiance`, SH of the distant radiance) at p with unit normal n.
  // `visibility_out`, when given, receives the visibility SH. `extra_log`, when given, is more
  // log-SH visibility added to the blockers' sum before the exponential (the terrain's cast
  // shadow, [Giraud] sec. 4.1), so all of it shadows in one exponential.
  // `with_lights` false leaves the local lights out (they reach receivers another way:
  // components::LocalLightRouting).
  glm::vec3 irradiance(const sh::CoeffsRgb<N>& radiance, const glm::vec3& p, const glm::vec3& n,
                       sh::Coeffs<N>* visibility_out = nullptr,
                       const sh::Coeffs<N>* extra_log = nullptr, bool with_lights = true) const;
  // What irradiance() does after log_visibility: shading from a given (depth-limited) log sum
  // at p with unit normal n (lights, kProduct or kLogBrdf). For ReceiverClusters.
  glm::vec3 irradiance_from_log(const sh::CoeffsRgb<N>& radiance, const glm::vec3& p,
                                const glm::vec3& n, const sh::Coeffs<N>& log_v,
                                sh::Coeffs<N>* visibility_out = nullptr,
                                bool with_lights = true) const;
  // How much of a distant light's disc (unit `direction`, angular radius `angular_radius`) the
  // blockers leave visible from p: the product over the blockers near p (the grid's candidates:
  // spheres of groups whose bound has sin(angular radius) above min_sin there, so a shadow
  // reaches about r / min_sin from its object) of 1 - the share of the disc the sphere's cap covers
  // (two discs' overlap, small-angle; a point light: in or out). 0 inside a sphere. Exact where one
  // sphere covers the disc; the product treats overlapping blockers as independent. For the
  // environment's key lights
  // ([Ambrosj16] ch. 4): a sharp sun shadow where the SH visibility can only give a soft one.
  float key_light_visibility(const glm::vec3& p, const glm::vec3& direction,
                             float angular_radius) const;
  // irradiance() for many receivers; `visibility` may be empty (not wanted) or one per point.
  void shade(const sh::CoeffsRgb<N>& radiance, std::span<const glm::vec3> points,
             std::span<const glm::vec3> normals, std::span<sh::Coeffs<N>> visibility,
             std::span<glm::vec3> irradiance) const;

  // Radiance reflected towards `view` (unit, from p to the eye) by a normalised Phong lobe of
  // settings().phong_exponent about the reflected view direction, shadowed by the blockers:
  // the lobe's log-ZH is added to the log-visibility before one exponential ([Giraud] sec. 5,
  // eq. 27). Throws std::logic_error when phong_exponent is 0.
  glm::vec3 glossy_radiance(const sh::CoeffsRgb<N>& radiance, const glm::vec3& p,
                            const glm::vec3& n, const glm::vec3& view) const;
  // The same with a given lobe (one per material: phong_lobe) and, when given, more log-SH
  // visibility in the sum (the terrain's cast shadow, as for irradiance()).
  glm::vec3 glossy_radiance(const sh::CoeffsRgb<N>& radiance, const glm::vec3& p,
                            const glm::vec3& n, const glm::vec3& view, const PhongLobe<N>& lobe,
                            const sh::Coeffs<N>* extra_log = nullptr) const;

  // The log-SH lobe of `exponent` (> 0, else std::invalid_argument) with floor `epsilon`;
  // epsilon 0: fitted_phong_epsilon(exponent). Costs a few milliseconds: build once per material.
  static PhongLobe<N> phong_lobe(float exponent, float epsilon = 0);
  // The floor for a Phong exponent: of 65 values over [0.001, 0.5] (log scale), the one whose
  // exponentiated log-ZH (exp_hyb) is closest, in L2 over the sphere, to the lobe's own ZH. No
  // single eps serves every exponent ([Giraud] fig. 6): broad lobes want a deep floor, sharp
  // ones a high one (docs/blocker_accumulation.md).
  static float fitted_phong_epsilon(float exponent);

  // Canonical log-ZH of max(cos theta / pi, eps) ([Giraud] sec. 5), by quadrature.
  static sh::Zonal<N> log_diffuse_zh(float epsilon);
  // Canonical log-ZH of the Phong lobe max((r + 1) / 2 pi cos^r, eps), log eps below the
  // horizon ([Giraud] eq. 27), and the lobe's own ZH (the SH BRDF it approximates).
  static sh::Zonal<N> log_phong_zh(float exponent, float epsilon);
  static sh::Zonal<N> phong_zh(float exponent);

 private:
  template <int>
  friend class ReceiverClusters;  // reads the groups, spheres and cut (receiver_clusters.h)

  // Calls add(sphere, scale) for every sphere the receiver at p sees, as the hierarchy's cut
  // decides (the bound, its spheres or both, blended).
  template <class Add>
  void for_each_blocker(const glm::vec3& p, Add&& add) const;
  // One blocker's log-SH added to `sum` by settings().blocker.log; returns its depth at the
  // axis in units of log eps (1 for the eps cap).
  float add_blocker_log(const BlockerView& v, sh::Coeffs<N>& sum) const;

  BlockerSettings settings_;
  float log_eps_;
  std::shared_ptr<const ClippedLogCap<N>> clipped_log_;  // BlockerLog::kClippedEigen
  sh::Zonal<N> clamped_cosine_;
  sh::Zonal<N> log_diffuse_;  // of max(cos / pi, brdf_epsilon)
  PhongLobe<N> phong_;        // settings' lobe (phong_exponent > 0)
  std::vector<WorldSphere> spheres_;
  std::vector<LightSource> lights_;
  std::vector<BlockerGroup> groups_;
  BlockerGrid grid_;  // over the groups' bounds
  float cut_sin_;     // sin(80 deg / N)
};

}  // namespace penumbra::blocker_accumulation
