// The probe-cloud traversal system in the job graph ([Sukys14] sec. 3.2, [Cupisz12]). Two
// systems, in this order:
//
//   probes.prepare (task)  reads ProbeCloudResource, ProbeSettingsResource; writes ProbeWalkState
//       When the resource's cloud pointer or generation differs from the walk's (a scene loaded
//       another cloud), or the walk settings changed, builds a new ProbeTetWalk (its fallback
//       grid: once per cloud) and bumps ProbeWalkState::generation, which invalidates every
//       entity's cached cell. Otherwise does nothing. A cloud the walk rejects (inconsistent
//       sizes) leaves no walk and its reason in ProbeWalkState::error.
//   probes.walk (chunks)   reads Transform, ProbeWalkState, ProbeSettingsResource, FrameTime;
//       writes ProbeAnchor, ProbeLighting, ProbeWalkReport
//       Per entity with all three of Transform, ProbeAnchor and ProbeLighting, in parallel over
//       chunks: the sample point (Transform * anchor offset) is located by walking from the
//       cached cell (a fresh locate when the cell is from another generation), the anchor keeps
//       the new cell, and the four probes' SH are interpolated at ProbeLighting's 3 bands and
//       written to ::irradiance, or blended into it when smoothing (ProbeSettingsResource; the
//       unsmoothed sample is not stored). A non-finite sample point (NaN/inf
//       transform or offset) is skipped: the entity keeps its anchor and lighting, and the
//       report names it. No cloud (or no walk): nothing is written. Skipped: an entity whose
//       sample point is bit-for-bit the one of its last walk, in the same cloud generation (its
//       sample cannot have changed; only the smoothing advances, towards that sample rebuilt
//       from the cached cell by ProbeTetWalk::at, no walk).
//
// Threading: probes.walk shares one immutable ProbeTetWalk between chunks; each chunk writes
// only its own rows and its own slot of the report's partials (merged in chunk order by the
// system's finish, so the report does not depend on the thread count).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "penumbra/components/probe_cloud_resource.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/probe_cloud/probe_tet_walk.h"

namespace penumbra::probe_cloud {

enum class ProbeSmoothing {
  kOff,          // irradiance = this frame's sample
  kExponential,  // irradiance += (sample - irradiance) * (1 - exp(-dt / time_constant))
};

// Resource: how the system walks and smooths.
struct ProbeSettingsResource {
  ProbeWalkSettings walk;
  ProbeSmoothing smoothing = ProbeSmoothing::kOff;
  float time_constant = 0.1f;  // seconds (kExponential); <= 0 acts as kOff
  // Frame time when the world has no components::FrameTime resource.
  float default_dt = 1.0f / 60.0f;
};

// Resource: the walk over the current cloud, owned by probes.prepare.
struct ProbeWalkState {
  std::shared_ptr<const ProbeTetWalk> walk;        // null: no cloud, or the cloud was rejected
  std::shared_ptr<const data::ProbeCloud> source;  // the resource's cloud the walk was made for
  std::uint64_t source_generation = 0;             // and its generation
  ProbeWalkSettings settings;                      // and the settings
  std::uint64_t generation = 0;                    // bumped at every new walk (never 0 then)
  std::string error;                               // why the last cloud was rejected
};

// Resource: what probes.walk did in the last frame.
struct ProbeWalkReport {
  std::size_t entities = 0;   // entities located (walked) this frame
  std::size_t unchanged = 0;  // entities skipped: same sample point and cloud as last frame
  std::size_t fallbacks = 0;  // of them, located by the fallback (no cache, teleport, cap)
  std::size_t steps = 0;      // cells stepped across, all entities together
  int max_steps = 0;          // the longest single walk
  std::size_t rejected = 0;   // entities skipped for a non-finite sample point
  // The first 20 of them, each named with the reason, then "... and N more".
  std::vector<std::string> errors;
};

// Adds ProbeCloudResource (holding `cloud`, generation 1 when given), ProbeSettingsResource,
// ProbeWalkState and ProbeWalkReport when absent.
void emplace_probe_cloud_resources(ecs::World& world,
                                   std::shared_ptr<const data::ProbeCloud> cloud = {});
void add_probe_cloud_systems(jobs::Schedule& schedule);

// The weight of this frame's sample in the exponential smoothing: 1 - exp(-dt / time_constant)
// (1 when time_constant <= 0 or dt is not finite); exposed for tests.
float smoothing_alpha(float dt, float time_constant);

}  // namespace penumbra::probe_cloud
