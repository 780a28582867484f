// What the blocker accumulation system computed for each point of an entity's Receiver:
// visibility as SH (4 bands, 16 coefficients per point), RGB irradiance (W/m^2, linear) and the
// radiance leaving the point towards the camera (W/m^2/sr) by the entity's Material: albedo E / pi
// for a Lambertian one, the albedo times the shadowed Phong lobe for a glossy one.
// `indirect` is the one-bounce irradiance from spherical lights (systems/spherical_lights,
// [Guerrero08]), its own term so direct and indirect can be shown and measured apart; null when
// that system is off or absent. `irradiance` and `radiance` are the direct light only.
// Published as shared immutable arrays, replaced rather than changed (as TerrainLighting).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::components {

struct ReceiverLighting {
  static constexpr int kBands = 4;
  using Visibility = std::array<float, kBands * kBands>;
  std::shared_ptr<const std::vector<Visibility>> visibility;  // one per receiver point
  std::shared_ptr<const std::vector<glm::vec3>> irradiance;   // one per receiver point
  std::shared_ptr<const std::vector<glm::vec3>> radiance;     // one per receiver point
  std::shared_ptr<const std::vector<glm::vec3>> indirect;     // one per receiver point, or null
  // The local lights' direct irradiance through spherical_lights.gather (LocalLightRouting
  // kSphereLightGather; `irradiance` then leaves them out), one per receiver point, or null.
  std::shared_ptr<const std::vector<glm::vec3>> local;
};

}  // namespace penumbra::components
