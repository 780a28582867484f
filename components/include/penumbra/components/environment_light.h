// The distant environment light, a world resource: an HDR map and its SH projection, and the
// light sources found in it with the map's occluded environment maps (OEMs, [Ambrosj16] ch. 4;
// written by systems/environment, environment_light_update.h; empty until then).
// Writers (the environment stage, the demo) bump `version` when the map or its SH change;
// rotating the sky only changes rotation_z (readers re-shade from stored transfer vectors).
// `radiance` always holds the SH of the whole map, sources included; readers that know nothing
// of the sources keep using it unchanged.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "penumbra/sh/basis.h"

namespace penumbra::data {
struct EnvironmentMap;  // penumbra/data/environment_map.h
}

namespace penumbra::components {

// A bright source found in the map (a sun, a lamp), as a small directional light. All in the
// map's own frame (unrotated: rotate by rotation_z like `radiance`).
struct EnvironmentSource {
  glm::vec3 direction{0, 0, 1};  // unit, from the scene towards the source, z-up
  float angular_radius = 0;      // radians (3 standard deviations of its texels, [Ambrosj16])
  glm::vec3 radiance{0};         // mean RGB radiance over its texels
  glm::vec3 irradiance{0};       // RGB radiance x solid angle: irradiance at normal incidence
  float energy_share = 0;        // share of the map's luminous energy in its texels
};

struct EnvironmentLight {
  std::shared_ptr<const data::EnvironmentMap> map;  // may be null when only SH is known
  sh::CoeffsRgb<sh::kDefaultBands> radiance{};      // SH of the map's radiance, unrotated
  float rotation_z = 0;  // radians, counter-clockwise about +z (the map's world orientation)
  std::uint64_t version = 0;
  // A scale on all of the map's light above (SH, sources, OEMs), >= 0: the sky dimming at dusk
  // without a new map. Every reader multiplies it in; changing it does not bump `version`.
  float intensity = 1.0f;
  // Sources, brightest first (at most 8), and the 2^sources.size() OEM SH sets: index = mask of
  // the sources still in the map (bit j set: source j present), so the last set is the whole
  // map and set 0 the map without any source. Unrotated, like `radiance`. Empty: none detected.
  std::vector<EnvironmentSource> sources;
  std::vector<sh::CoeffsRgb<3>> oem_sh3;                 // 3 bands ([Ambrosj16] sec. 4.2)
  std::vector<sh::CoeffsRgb<sh::kDefaultBands>> oem_sh;  // kDefaultBands
  std::uint64_t sources_version = 0;  // the `version` the sources and OEMs were found for
};

// What a lighting system does with the sources (its settings hold one):
//  - kShOnly: nothing apart; the whole map's SH (the sun blurred into it, its shadow soft);
//  - kKeyLights: each source no wider than the system's limit is a key light with its own
//    shadow, the rest of the map in SH (its OEM, [Ambrosj16] ch. 4).
enum class EnvironmentSources { kShOnly, kKeyLights };

// The sources of `env` taken as key lights: bit j for source j, those no wider than
// max_angular_radius (radians), when the detection is complete for the current map (the
// sources_version matches and every OEM set is there); 0 otherwise. The SH left for the rest of
// the map is then oem_sh[oem_sh.size() - 1 - mask] (every other source still in it).
inline std::size_t key_light_mask(const EnvironmentLight& env, float max_angular_radius) {
  if (env.sources.empty() || env.sources.size() > 16 || env.sources_version != env.version ||
      env.oem_sh.size() != (std::size_t{1} << env.sources.size()))
    return 0;
  std::size_t mask = 0;
  for (std::size_t j = 0; j < env.sources.size(); ++j)
    if (env.sources[j].angular_radius <= max_angular_radius) mask |= std::size_t{1} << j;
  return mask;
}

// The map's SH without the sources in `mask` (bit j: source j taken out as a key light), every
// other source still in it; mask 0: the whole map's SH. Needs the OEM sets (key_light_mask).
inline const sh::CoeffsRgb<sh::kDefaultBands>& sh_without(const EnvironmentLight& env,
                                                          std::size_t mask) {
  return mask ? env.oem_sh[env.oem_sh.size() - 1 - mask] : env.radiance;
}

// A source's direction in the world: turned by the map's rotation_z about +z (unit).
inline glm::vec3 world_direction(const EnvironmentSource& s, float rotation_z) {
  const float c = std::cos(rotation_z), n = std::sin(rotation_z);
  const glm::vec3& d = s.direction;
  return glm::normalize(glm::vec3(c * d.x - n * d.y, n * d.x + c * d.y, d.z));
}

}  // namespace penumbra::components
