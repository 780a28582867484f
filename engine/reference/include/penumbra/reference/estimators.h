// Monte Carlo estimators of the reference integrator: ground truth, with a standard error, for
// every accuracy test and chart of the project.
//
//  - environment_irradiance: E(p, n) = int L_env(w) V(p, w) max(0, n.w) dw (W/m^2), or with an
//    albedo the outgoing diffuse radiance albedo / pi * E. Stratified; by default multiple
//    importance sampling (Veach 1997, ch. 9: multi-sample model, power or balance heuristic)
//    of cosine-weighted hemisphere sampling and the map's luminance distribution (environment.h).
//  - light_irradiance: the same integral over the scene's spherical lights, each sampled
//    uniformly in the cone of directions it subtends (PBRT 3rd ed. sec. 14.2.2); the lights
//    themselves never occlude. A receiver inside or on a light gets nothing from that light.
//  - visibility_sh<N>: V_i = int V(p, w) y_i(w) W(w) dw for the N-band basis of
//    penumbra/sh/basis.h, with W = 1 (whole sphere), [n.w > 0] (hemisphere) or max(0, n.w)
//    (cosine: the diffuse transfer vector, sum_i L_i T_i = irradiance). Lights do not occlude.
//  - indirect_irradiance: one diffuse bounce off the occluders' albedo (scene.h),
//    E_ind(p, n) = int L_1(x(p, w)) max(0, n.w) dw with x(p, w) the first occluder hit along w
//    and L_1(x) = albedo(x) / pi * E_direct(x, n_x), E_direct the environment + spherical-light
//    irradiance at x (what the two estimators above estimate there, with the scene's
//    visibility; n_x the normal of the side hit). Directions that leave the scene add nothing
//    (that is the direct term). Stratified cosine-weighted directions at p; at each hit
//    BounceOptions::bounce_samples direct samples, environment by MIS (as above) and each
//    light's cone. Unbiased: each direction's contribution albedo(x) x (unbiased estimate of
//    E_direct(x)) has expectation pi L_1(x) = L_1 cos / pdf. Total irradiance (direct + one
//    bounce) = combine(combine(environment, light), indirect): the three use separate streams.
//    Cost per receiver: `samples` first-hit rays, plus at each hit of a reflective occluder
//    about bounce_samples environment shadow rays and bounce_samples per light.
//
// V(p, w) is 1 when the ray from p towards w leaves the scene's occluders (scene.h) unhit.
// A receiver inside an occluder sphere sees nothing: every estimate is 0 there.
//
// Error bars: every number comes with the standard error of its mean, estimated from two
// independent samples per stratum (sampling.h): unbiased for the variance of the stratified
// estimator, so it keeps stratification's gain (the error falls at least as fast as
// 1/sqrt(samples), faster where the integrand is smooth). `dof` counts the strata whose two
// samples differ, the degrees of freedom of that variance estimate: (estimate - exact) /
// std_error is roughly Student-t with `dof` degrees of freedom. With dof >= 30, |error| > 4
// std_error has a probability near 3e-4 (`dof` is the smallest such count over the channels or
// coefficients with a nonzero error). With few (a small feature -- a thin sliver of occluder, a
// tiny bright texel -- crossing few strata) the error bar is itself uncertain, and can even be 0
// while the estimate is off: raise `samples` until dof >= 30. (A feature that no sample hits is
// invisible to any Monte Carlo error bar.)
//
// Ray offsets: shadow rays start at p + offset * n (n the unit receiver normal) with
// offset = ray_offset when > 0, else 1e-5 * max(scene.extent(), max(|p.x|, |p.y|, |p.z|)):
// float positions carry a relative error near 1e-7, so this clears the surface p lies on with
// 100x margin, while the angular band it can misclassify (offset / feature size) stays far below
// the error bars. With visibility_sh over the whole sphere a zero normal is allowed and means no
// offset (a point in free space, e.g. a light probe). The light cones are those seen from p
// itself; only their shadow rays start at the offset point and end at the light's near surface.
//
// Determinism: receiver i draws from its own random stream, seeded by (seed, i, estimator), so
// results are bit-identical for any thread count and any scheduling.
// Threading: the batch functions run tbb::parallel_for in the caller's task arena (wrap them in
// a tbb::task_arena to bound the threads) and may be called concurrently.
// Errors: std::invalid_argument for samples < 1 (or bounce_samples < 1), a non-finite position, a
// zero or non-finite normal (naming the receiver index), or a negative / non-finite albedo or ray
// offset.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/reference/scene.h"
#include "penumbra/sh/basis.h"

namespace penumbra::reference {

struct Receiver {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // any length > 0; normalised internally
};

struct RgbEstimate {
  glm::vec3 mean{0.0f};
  glm::vec3 std_error{0.0f};  // standard error of `mean`, per channel
  std::uint32_t samples = 0;  // directions drawn
  std::uint32_t rays = 0;     // shadow rays cast (zero-contribution samples cast none)
  std::uint32_t dof = 0;      // degrees of freedom of std_error: see "Error bars"
};

template <int N>
struct ShEstimate {
  sh::Coeffs<N> mean{};
  sh::Coeffs<N> std_error{};
  std::uint32_t samples = 0;
  std::uint32_t rays = 0;
  std::uint32_t dof = 0;
};

struct SamplingOptions {
  // Directions per receiver (per light for light_irradiance). Rounded down to 2 x a grid of
  // strata (x 2 strategies under MIS); RgbEstimate::samples says what was used.
  int samples = 256;
  std::uint64_t seed = 0;
  bool stratified = true;  // false: independent uniform points (error exactly ~1/sqrt(n))
  float ray_offset = 0;    // metres along the normal; 0 = automatic (see above)
};

enum class EnvironmentStrategy { kMis, kCosine, kEnvironment };
enum class MisHeuristic { kPower, kBalance };  // power: exponent 2

struct IrradianceOptions : SamplingOptions {
  EnvironmentStrategy strategy = EnvironmentStrategy::kMis;
  MisHeuristic heuristic = MisHeuristic::kPower;
  std::optional<glm::vec3> albedo;  // set: report albedo / pi * E (radiance) instead of E
};

struct LightOptions : SamplingOptions {
  std::optional<glm::vec3> albedo;
};

enum class VisibilityDomain { kSphere, kHemisphere, kCosine };

struct VisibilityOptions : SamplingOptions {
  VisibilityDomain domain = VisibilityDomain::kSphere;
};

struct BounceOptions : SamplingOptions {
  // `samples`: cosine-weighted first-hit directions at the receiver, rounded down to 2 x a grid
  // of strata (RgbEstimate::samples says what was used; RgbEstimate::rays counts every ray).
  // At each hit of a reflective occluder, E_direct is estimated with bounce_samples directions
  // for the environment (bounce_samples / 2 per MIS strategy, at least 1 each) and
  // bounce_samples cone directions per light, each set stratified over a grid rounded down as
  // above. More per hit lowers the variance of each contribution, not its mean.
  int bounce_samples = 4;
  MisHeuristic heuristic = MisHeuristic::kPower;  // of the environment's MIS at the hits
};

// Batches: one result per receiver, in order. With no environment map every result is zero.
std::vector<RgbEstimate> environment_irradiance(const Scene& scene,
                                                std::span<const Receiver> receivers,
                                                const IrradianceOptions& options = {});
std::vector<RgbEstimate> light_irradiance(const Scene& scene, std::span<const Receiver> receivers,
                                          const LightOptions& options = {});
template <int N>
std::vector<ShEstimate<N>> visibility_sh(const Scene& scene, std::span<const Receiver> receivers,
                                         const VisibilityOptions& options = {});
// One diffuse bounce (see above). Zero (no rays) when no occluder has a nonzero albedo or
// nothing emits.
std::vector<RgbEstimate> indirect_irradiance(const Scene& scene,
                                             std::span<const Receiver> receivers,
                                             const BounceOptions& options = {});

// Sum of two independent estimates (e.g. environment + lights, then + indirect): means add,
// variances add; dof is the smaller nonzero one (conservative).
RgbEstimate combine(const RgbEstimate& a, const RgbEstimate& b);

// One receiver per sample of a placed height field: positions as in scene.h, normals from
// central differences of the heights (one-sided at the borders), row-major (index y * width + x).
std::vector<Receiver> height_field_receivers(const HeightFieldInstance& field);

}  // namespace penumbra::reference
