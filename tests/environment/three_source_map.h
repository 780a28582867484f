// A deterministic map with three small sources, built in code (issue 15: n = 3 key lights; no
// map in ../shared/data/hdri has three): studio.exr (two lamps, docs/environment.md "Sources
// found") with one sun disc added, every texel whose centre lies within kSunRadiusDeg of
// kSunDirection set to kSunRadiance. Used by the detection test
// (three_source_map_test.cpp) and the environment bench group (environment_key_lights.cpp).
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"
#include "synthetic_maps.h"

namespace penumbra::test::three_sources {

// The added sun: azimuth 300 deg, elevation 30 deg (z-up, azimuth from +x towards +y), 60 deg
// and more from both lamps, so that its halo does not touch theirs.
constexpr float kSunAzimuthDeg = 300.0f;
constexpr float kSunElevationDeg = 30.0f;
constexpr float kSunRadiusDeg = 2.5f;
inline const glm::vec3 kSunRadiance{1200.0f, 1100.0f, 950.0f};  // warm white, linear RGB

// studio.exr's lamps as the detection finds them on studio.exr alone (default settings, the
// table in docs/environment.md): azimuth / elevation / radius in degrees.
struct Lamp {
  float azimuth_deg, elevation_deg, radius_deg;
};
constexpr Lamp kStudioLamps[2] = {{81.33f, 41.70f, 3.81f}, {241.40f, 0.30f, 10.97f}};

inline glm::vec3 sun_direction() {
  return dir_deg(kSunAzimuthDeg, kSunElevationDeg);
}

// `studio` (studio.exr as loaded) with the sun added; the source name gains " + sun".
inline data::EnvironmentMap add_sun(data::EnvironmentMap studio) {
  add_disc(studio, sun_direction(), kSunRadiusDeg, kSunRadiance);
  studio.source += " + sun";
  return studio;
}

}  // namespace penumbra::test::three_sources
