#include "penumbra/systems/environment/environment_light_update.h"

#include <utility>

#include "penumbra/data/environment_map.h"

namespace penumbra::environment {

components::EnvironmentSource to_environment_source(const DetectedSource& s) {
  components::EnvironmentSource out;
  out.direction = s.direction;
  out.angular_radius = s.angular_radius;
  out.radiance = s.radiance;
  out.irradiance = s.irradiance;
  out.energy_share = s.energy_share;
  return out;
}

LightSourceDetection update_environment_light(components::EnvironmentLight& light,
                                              const DetectionSettings& settings) {
  if (!light.map) {
    light.sources.clear();
    light.oem_sh3.clear();
    light.oem_sh.clear();
    light.sources_version = light.version;
    return {};
  }
  LightSourceDetection d = detect_light_sources(*light.map, settings);
  OccludedEnvironmentMaps oems = build_occluded_environment_maps(*light.map, d);
  std::vector<components::EnvironmentSource> sources;
  for (const DetectedSource& s : d.sources) sources.push_back(to_environment_source(s));
  light.sources = std::move(sources);
  light.oem_sh3 = std::move(oems.sh3);
  light.oem_sh = std::move(oems.sh);
  light.sources_version = light.version;
  return d;
}

}  // namespace penumbra::environment
