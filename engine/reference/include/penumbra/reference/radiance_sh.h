// Radiance capture for light probes: the SH projection of the incident radiance at a point in
// free space, over the whole sphere, by ray tracing the reference scene (scene.h). The probe
// bake (systems/probe_bake) turns it into the cloud's irradiance SH ([Sukys14] sec. 3.1: light is
// "captured and stored as a spherical harmonic function" at each probe position).
//
//   L_i(p) = int L(p, w) y_i(w) dw,   i < N^2, per RGB channel (engine/sh basis, N = 2..4 bands)
//
// with L(p, w) the radiance arriving at p from direction w:
//  - direct: the environment map where the ray from p leaves the scene's occluders, and every
//    spherical light whose near surface is reached before an occluder (lights never occlude);
//  - one diffuse bounce (options.bounce): where the ray first hits an occluder x with a nonzero
//    albedo, L = albedo(x) / pi * E_direct(x, n_x), E_direct the environment + light irradiance
//    at x with the scene's visibility, estimated there with bounce_samples directions per source
//    exactly as indirect_irradiance does (estimators.h; docs/reference.md "One diffuse bounce").
//
// options.direct = false with options.bounce keeps the bounce alone (the probe bake's "light
// decoupling", [Sukys14] sec. 3.1.2): no environment or light term at the point itself, the
// bounce's own direct light at the hit unchanged; the environment-map and light samples (and
// their shadow rays) are then skipped.
//
// Sampling (per point, `samples` rounded down to 2 x a grid of H strata of the unit square):
// in every stratum two independent sets of
//  - one uniform sphere direction (density 1/(4 pi)): its first hit gives the bounce term or,
//    when it escapes, the environment with the MIS weight against map sampling;
//  - one environment-map direction (environment.h), MIS-weighted (Veach 1997, ch. 9), a shadow
//    ray to infinity;
//  - one direction per spherical light, uniform in the cone it subtends (PBRT 3rd ed.
//    sec. 14.2.2), a shadow ray to its near surface.
// Each set is an unbiased estimate of all 3 N^2 coefficients; the paired-strata standard error
// (sampling.h) is reported per coefficient, `dof` as in estimators.h.
//
// Back faces (probe validity, Unity adaptive probe volumes / DDGI): when options.back_face is
// set, every sphere direction's hit is passed to it; a hit it calls a back face (the ray leaves
// a solid: the point is inside geometry) adds no radiance (as DDGI) and is counted. The nearest
// back-face hit is reported (escape_dir, escape_distance): the direction in which the point is
// nearest to leaving the solid (the bake's "virtual offset").
//
// Conventions as estimators.h: the point has no normal and rays start at the point itself (no
// offset; a point exactly on a surface gives a finite, documented estimate: about half its rays
// hit that surface at distance ~0). Radiance in the scene's units; a uniform sky of radiance L
// and no occluders gives L sqrt(4 pi) in coefficient 0 and 0 elsewhere.
// Determinism: point i draws from its own stream (seed, first_index + i, salt 5): bit-identical
// results for any thread count. Threading: tbb::parallel_for in the caller's arena; `back_face`
// must be safe to call concurrently. Errors: std::invalid_argument for samples < 2, bounce_samples
// < 1, a non-finite point (naming its index).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/reference/estimators.h"
#include "penumbra/reference/scene.h"
#include "penumbra/sh/basis.h"

namespace penumbra::reference {

struct RadianceShOptions : SamplingOptions {
  bool direct = true;      // the environment and the lights as seen from the point
  bool bounce = true;      // one diffuse bounce off the occluders' albedo
  int bounce_samples = 4;  // direct samples per source at each reflective hit (BounceOptions)
  MisHeuristic heuristic = MisHeuristic::kPower;
  // Point i draws from stream first_index + i: a caller splitting one batch into chunks (the
  // bake, for its progress bar) passes each chunk's offset and gets the same numbers.
  std::uint64_t first_index = 0;
  // (origin, unit direction, hit) -> is it a back face? Empty: no hit is a back face.
  std::function<bool(const glm::vec3&, const glm::vec3&, const Hit&)> back_face;
};

template <int N>
struct RadianceShEstimate {
  sh::CoeffsRgb<N> mean{};       // radiance SH per channel
  sh::CoeffsRgb<N> std_error{};  // standard error of each coefficient
  std::uint32_t samples = 0;     // sphere directions drawn (2 H)
  std::uint32_t rays = 0;        // every ray cast (first-hit, shadow, bounce)
  std::uint32_t dof = 0;         // as RgbEstimate::dof
  std::uint32_t hits = 0;        // sphere directions that hit an occluder
  std::uint32_t back_face_hits = 0;
  glm::vec3 escape_dir{0.0f};  // unit direction of the nearest back-face hit; 0 if none
  float escape_distance = std::numeric_limits<float>::infinity();

  float back_face_share() const {
    return samples ? static_cast<float>(back_face_hits) / static_cast<float>(samples) : 0.0f;
  }
};

// One estimate per point, in order. N = 2, 3 or 4.
template <int N>
std::vector<RadianceShEstimate<N>> radiance_sh(const Scene& scene,
                                               std::span<const glm::vec3> points,
                                               const RadianceShOptions& options = {});

}  // namespace penumbra::reference
