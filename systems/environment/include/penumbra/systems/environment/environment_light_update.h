// Fills the EnvironmentLight resource's sources and OEM sets from its map (detection +
// occluded_environment_maps), re-run when the map changes ([Ambrosj16] ch. 4).
//
// Contract: update_environment_light reads light.map; with a null map it clears the sources and
// sets. It leaves map, radiance and rotation_z alone and does not bump `version` (the map's SH
// is unchanged); it sets sources_version = version. Throws what detect_light_sources throws (the
// map's name and the reason) with the resource unchanged. Threading: the caller holds the
// resource for writing (a system declaring EnvironmentLight in its writes).
#pragma once

#include "penumbra/components/environment_light.h"
#include "penumbra/systems/environment/light_source_detection.h"
#include "penumbra/systems/environment/occluded_environment_maps.h"

namespace penumbra::environment {

// The plain source of the resource, from a detected one.
components::EnvironmentSource to_environment_source(const DetectedSource& s);

// Detects, builds the OEMs and stores both; returns the detection for reporting.
LightSourceDetection update_environment_light(components::EnvironmentLight& light,
                                              const DetectionSettings& settings = {});

// Whether the sources are stale: sources_version != version.
inline bool sources_stale(const components::EnvironmentLight& light) {
  return light.sources_version != light.version;
}

}  // namespace penumbra::environment
