// How a receiving surface reflects light: a diffuse albedo and a Phong exponent ([Giraud]
// sec. 5). Optional beside a Receiver: the blocker system then publishes the outgoing radiance
// (ReceiverLighting::radiance); without it the surface is white and Lambertian. render_extract
// draws an entity's mesh with this albedo when it has one (else its BaseColor).
#pragma once

#include <glm/vec3.hpp>

namespace penumbra::components {

struct Material {
  glm::vec3 albedo{0.8f};  // linear reflectance, per channel in [0, 1]
  // 0: Lambertian. > 0: a normalised Phong lobe (r + 1) / 2 pi cos^r about the reflected view
  // direction (towards the Camera resource), scaled by the albedo.
  float phong_exponent = 0;
};

}  // namespace penumbra::components
