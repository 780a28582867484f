#include "sky_split.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "penumbra/systems/environment/light_source_detection.h"

namespace penumbra::tune {

SplitSky split_sky(const data::EnvironmentMap& map, float rotation_z, int sources,
                   float max_radius) {
  SplitSky out;
  out.rest = map;
  if (sources <= 0) return out;
  environment::DetectionSettings ds;
  ds.source_count = sources;
  const environment::LightSourceDetection det = environment::detect_light_sources(map, ds);
  const float c = std::cos(rotation_z), s = std::sin(rotation_z);
  for (const environment::DetectedSource& src : det.sources) {
    if (src.angular_radius > max_radius) continue;  // a glow stays in the SH
    for (std::uint32_t t : src.texels)
      for (int k = 0; k < 3; ++k) out.rest.rgb[3 * static_cast<std::size_t>(t) + k] = 0.0f;
    const glm::vec3& d = src.direction;  // as components::world_direction turns it
    KeyLight key;
    key.direction = glm::normalize(glm::vec3(c * d.x - s * d.y, s * d.x + c * d.y, d.z));
    key.angular_radius = src.angular_radius;
    key.irradiance = src.irradiance;
    out.keys.push_back(key);
  }
  return out;
}

}  // namespace penumbra::tune
