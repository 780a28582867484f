// The sky as the lighting systems shade it (components/environment_light.h, EnvironmentSources::
// kKeyLights): the bright sources found in the map (systems/environment, [Ambrosj16] ch. 4) no
// wider than max_radius become key lights with their own exact shadows, and the rest of the map
// (their texels removed) is shaded in SH. The terrain system adds each key light with the
// terrain's horizon in its azimuth, the blocker system with its disc occluded by the blockers;
// the tuners do the same so they measure what the systems compute.
// Threading: pure function.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/data/environment_map.h"

namespace penumbra::tune {

struct KeyLight {
  glm::vec3 direction{0, 0, 1};  // unit, world (the map's rotation applied), towards the source
  float angular_radius = 0;      // radians
  glm::vec3 irradiance{0};       // W/m^2 at normal incidence, unoccluded
};

struct SplitSky {
  data::EnvironmentMap rest;  // the map with the key lights' texels set to 0
  std::vector<KeyLight> keys;
};

// `sources`: at most this many (the demo's 1); max_radius: TerrainShadowSettings'
// key_light_max_radius (0.2 rad). sources = 0: the whole map in SH, no key lights.
SplitSky split_sky(const data::EnvironmentMap& map, float rotation_z, int sources = 1,
                   float max_radius = 0.2f);

}  // namespace penumbra::tune
