// The environment system in the job graph: one task system,
//
//   environment.sources  writes EnvironmentLight, EnvironmentSettings
//       When the map's sources are stale (EnvironmentLight::sources_version != version: a new
//       map), finds them and builds the OEM sets (update_environment_light, [Ambrosj16] ch. 4);
//       otherwise nothing. A map the detection rejects (NaN texels, ...) leaves no sources and
//       its message in EnvironmentSettings::error (the SH alone then lights the scene).
//
// Register it before the systems that read EnvironmentLight (terrain_shadow.compose,
// blockers.shade): they pick the key lights up the same frame. Detection costs about 7 ms for a
// 512 x 256 map and 25 ms for 1024 x 512 (docs/environment.md), once per map change.
#pragma once

#include <string>

#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/environment/light_source_detection.h"

namespace penumbra::environment {

// Resource: the detection's settings, and what the last detection said.
struct EnvironmentSettings {
  DetectionSettings detection;
  std::string error;           // the last rejected map's message ("": none)
  std::size_t detections = 0;  // maps processed so far
};

// Adds EnvironmentSettings (with `detection`) when absent.
void emplace_environment_resources(ecs::World& world, const DetectionSettings& detection = {});
// Registers environment.sources.
void add_environment_systems(jobs::Schedule& schedule);

}  // namespace penumbra::environment
