// Adaptive placement ([Sukys14] sec. 3.1): both methods start from the uniform grid, capture
// light at the probes through a callback (the bake's capture: reference::radiance_sh), and
// return positions only; the bake then captures, validates and tetrahedralizes them like any
// placement. Probes inside solids (back-face share above invalid_share) take no part: they
// neither merge nor spawn nor move, and are left for validity.
//
// Spawn and merge (sec. 3.1.1, 3.1.3). Each iteration: Delaunay edges of the current probes;
// per edge the 26-direction contrast (probe_sampling.h);
//  - merge: contrast < merge_contrast and length <= merge_length spacings: both probes are
//    replaced by one at the midpoint (each probe in at most one merge per iteration, the
//    lowest contrasts first); probes made by a spawn never merge (else a spawned midpoint and
//    its parent, similar by construction at half the distance, would merge back);
//  - spawn: contrast > spawn_contrast and length >= spawn_length spacings: a probe at the
//    midpoint (highest contrasts first), unless the midpoint is inside a solid;
//  then the new probes are captured. Stops (sec. 3.1.1's criteria) when a) an iteration changes
//  nothing, b) max_iterations ran, or c) the probe count reached max_probes (spawns beyond the
//  cap are dropped, highest contrasts kept).
//
// Gradient ascent (sec. 3.1.2, 3.1.3): light decoupling -- the probes capture indirect light
// only (the bounce; the callback's `indirect` flag); each lit probe moves along its irradiance
// vector (probe_sampling.h) by step x spacing x |vector|; a move that lands where the captured
// irradiance is zero (behind geometry) or inside a solid is reverted and that probe's step
// halved ("second order" ascent); stops after max_iterations or when every move is below
// min_step spacings. Then the black probes (no indirect light; not inside solids) are reduced by
// k-means to ceil(count x black_fraction) clusters (sec. 3.1.3), each represented by its member
// nearest the centroid (a centroid can lie inside a solid).
// Deterministic: fixed orders; the callback's streams are its business (the bake numbers every
// captured point).
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/systems/probe_bake/bake_scene.h"

namespace penumbra::probe_bake {

// Captures irradiance SH (3 bands^2 floats per point) and back-face shares at `points`;
// `indirect`: the bounce only (light decoupling).
using CaptureFn = std::function<void(std::span<const glm::vec3> points, bool indirect,
                                     std::vector<float>& sh, std::vector<float>& share)>;

struct SpawnMergeSettings {
  float spawn_contrast = 0.35f;  // contrast above: spawn at the midpoint
  float merge_contrast = 0.08f;  // contrast below: merge into the midpoint
  float spawn_length = 0.3f;     // spacings: shorter edges never spawn
  float merge_length = 1.05f;    // spacings: longer edges never merge
  float dark_floor = 0.02f;      // contrast floor, relative to the mean probe luminance
  int max_iterations = 4;
  std::size_t max_probes = 4000;
};

struct AdaptiveReport {
  enum class Stop { kNoChange, kIterations, kProbeCap, kSmallStep };
  Stop stop = Stop::kNoChange;
  int iterations = 0;
  std::size_t initial = 0, spawned = 0, merged = 0;              // spawn and merge
  std::size_t moves = 0, reverted = 0, black = 0, clusters = 0;  // gradient
  std::size_t captured = 0;         // points captured by the placement (beyond the bake's own)
  std::vector<std::size_t> counts;  // probe count after each iteration
};

std::vector<glm::vec3> spawn_merge_points(const BakeScene& scene, const ProbeVolume& volume,
                                          int bands, float invalid_share,
                                          const SpawnMergeSettings& settings,
                                          const CaptureFn& capture,
                                          AdaptiveReport* report = nullptr);

struct GradientSettings {
  float step = 0.5f;       // spacings per unit irradiance-vector length, first iteration
  float min_step = 0.05f;  // spacings: a move below this counts as converged
  int max_iterations = 8;
  float black_fraction = 0.125f;  // k-means: clusters = ceil(black probes x this)
  int kmeans_iterations = 20;
};

std::vector<glm::vec3> gradient_points(const BakeScene& scene, const ProbeVolume& volume, int bands,
                                       float invalid_share, const GradientSettings& settings,
                                       const CaptureFn& capture, AdaptiveReport* report = nullptr);

}  // namespace penumbra::probe_bake
