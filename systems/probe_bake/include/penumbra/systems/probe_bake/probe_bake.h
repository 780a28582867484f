// The probe bake (issue 14): placement -> irradiance capture -> validity -> probe cloud.
//  1. placement (probe_placement.h: the uniform grid, spawn and merge, gradient ascent) over the
//     scene's probe volume;
//  2. capture: reference::radiance_sh at every probe (direct + one diffuse bounce, radiance_sh.h)
//     with back faces classified by BakeScene::inside just before each hit; the radiance SH is
//     convolved to irradiance SH (sh::irradiance_convolve), the cloud's convention
//     (data/probe_cloud.h: E(n) = sum_i e_i y_i(n));
//  3. validity (probe_validity.h): virtual offset (a second capture at the moved point, streams
//     n + i), then dilation;
//  4. build_probe_cloud (Delaunay, [Sukys14] sec. 3.2) and validate_probe_cloud.
// Determinism: every probe's streams depend on (seed, its index) only, so the same scene and
// settings give the same cloud, byte for byte, for any thread count and chunking.
// Errors: std::invalid_argument for bad settings (bands outside 2..4, samples < 2, spacing
// not > 0).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "penumbra/data/probe_cloud.h"
#include "penumbra/reference/scene.h"
#include "penumbra/systems/probe_bake/bake_scene.h"
#include "penumbra/systems/probe_bake/probe_adaptive.h"
#include "penumbra/systems/probe_bake/probe_edge_rays.h"
#include "penumbra/systems/probe_bake/probe_placement.h"
#include "penumbra/systems/probe_bake/probe_validity.h"

namespace penumbra::probe_bake {

struct BakeSettings {
  int bands = data::kProbeDefaultBands;  // 2..4
  int samples = 1024;      // sphere directions per probe (radiance_sh; rounded to 2 x strata)
  int bounce_samples = 4;  // direct samples per source at each bounce hit
  bool bounce = true;
  std::uint64_t seed = 1;
  float spacing = 0;  // grid spacing in metres; 0: the scene's probes.spacing
  PlacementMethod placement = PlacementMethod::kGrid;
  bool validity = true;  // false: every probe keeps its own capture (the "before" of the docs)
  ValiditySettings validity_settings;
  // Edge rays ([Sukys14] sec. 3.2.2, probe_edge_rays.h) after placement and validity: the new
  // probes are captured like the others (streams after every earlier capture) and, with
  // validity on, dropped if invalid there (back-face share above invalid_share).
  EdgeRaySettings edge_rays;
  SpawnMergeSettings spawn_merge;  // PlacementMethod::kSpawnMerge (probe_adaptive.h)
  GradientSettings gradient;       // PlacementMethod::kGradient
  std::size_t chunk = 64;          // probes per progress step (no effect on the result)
};

struct ProbeRecord {
  glm::vec3 placed{0.0f};    // where placement put it
  glm::vec3 position{0.0f};  // where it was captured (placed + virtual offset)
  float back_face_share = 0;
  float dc_std_error = 0;  // largest standard error of the irradiance DC term over channels
  float dc = 0;            // the irradiance DC term, mean over channels
  ProbeState state = ProbeState::kValid;
  int edge_round = 0;  // 0: placed (or split); k >= 1: added by edge-ray round k
};

struct BakeReport {
  // Per probe of the cloud (before merging): the placed ones in order, then the second sides
  // of split probes (ValiditySettings::both_sides), then the edge-ray probes by round.
  std::vector<ProbeRecord> probes;
  std::size_t placed = 0;                                     // probes placement made
  std::size_t valid = 0, offset = 0, dilated = 0, black = 0;  // placed probes by state
  std::size_t split = 0;  // probes added on the other side of a thin solid (both_sides)
  // Edge rays: rounds run (stopped early when one adds nothing), probes added (kept), probes
  // dropped as invalid where they landed, and the rays' statistics summed over the rounds.
  int edge_rounds = 0;
  std::size_t edge_added = 0, edge_dropped = 0;
  EdgeRayStats edge;
  std::uint64_t rays = 0;
  double edge_seconds = 0;
  AdaptiveReport adaptive;           // spawn and merge / gradient ascent (probe_adaptive.h)
  double placement_seconds = 0;      // adaptive placement, its captures included
  std::uint64_t placement_rays = 0;  // rays of those captures (not in `rays`)
  double capture_seconds = 0, validity_seconds = 0, build_seconds = 0, total_seconds = 0;
  double mean_rel_std_error = 0;  // mean over lit captured probes of dc_std_error / dc
  double max_rel_std_error = 0;
  std::size_t merged = 0;    // probes merged by build_probe_cloud (offset onto another)
  std::size_t snapped = 0;   // coordinates build_probe_cloud moved onto the box's faces
  bool valid_cloud = false;  // validate_probe_cloud found nothing
  std::vector<std::string> validation_errors;
};

// progress(done, total) after every chunk of captures (total counts both capture passes).
using BakeProgress = std::function<void(std::size_t, std::size_t)>;

data::ProbeCloud bake_probe_cloud(const BakeScene& scene, const BakeSettings& settings,
                                  BakeReport* report = nullptr, const BakeProgress& progress = {});

// The same with an already built reference scene (tests reuse one for the reference values).
data::ProbeCloud bake_probe_cloud(const BakeScene& scene, const reference::Scene& traced,
                                  const BakeSettings& settings, BakeReport* report = nullptr,
                                  const BakeProgress& progress = {});

}  // namespace penumbra::probe_bake
