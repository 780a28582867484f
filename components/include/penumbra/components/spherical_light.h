// A local light: a sphere of uniform radiance ([Meier13] sec. 4.3, fig. 4.11).
// Seen from outside, every direction that meets the sphere carries `radiance`; a receiver at
// distance d > radius gets irradiance pi * radiance * (radius / d)^2 facing it unoccluded.
#pragma once

#include <glm/vec3.hpp>

namespace penumbra::components {

struct SphericalLight {
  glm::vec3 position{0.0f};  // world centre, metres
  float radius = 1.0f;       // metres; 0 means no light (culled)
  glm::vec3 radiance{1.0f};  // linear RGB, W / (m^2 sr)
};

// Which system gives receivers (ReceiverLighting) the direct light of the local lights:
// kBlockerSh: blockers.shade, the light's cap as SH radiance under the blockers' log-SH
// visibility (band-limited: a light small in the sky is blurred); kSphereLightGather:
// spherical_lights.gather, the light as a spherical light of [Guerrero08] (its average radiance
// by the tabulated w_theta, eq. 13-18, shadowed by every blocker sphere by eq. 23-24) into
// ReceiverLighting::local. Either way the terrain system lights the terrain, and the spherical
// lights' sample points see the local lights through the blockers' accumulation.
enum class LocalLightPath { kBlockerSh, kSphereLightGather };

// Resource (optional; absent: kBlockerSh), read by blockers.shade and spherical_lights.gather.
struct LocalLightRouting {
  LocalLightPath path = LocalLightPath::kBlockerSh;
};

}  // namespace penumbra::components
