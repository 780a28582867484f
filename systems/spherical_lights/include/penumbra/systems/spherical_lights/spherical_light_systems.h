// The spherical-light system in the job graph ([Guerrero08]): two task systems, registered after
// add_blocker_systems (they read its BlockerField and add to what blockers.shade wrote).
//
//   spherical_lights.reflect  reads Reflector, Transform, BlockerField, EnvironmentLight, Terrain,
//       SphericalLightSettingsResource; writes ReflectorRadiance, SphericalLightField
//       Pass 1 (reflector_lighting.h): per entity with a Reflector, a Transform and a
//       ReflectorRadiance, the direct light at its sample points (the blockers'
//       BlockerAccumulation: every sphere blocker and local light of the frame, the environment SH)
//       and each spherical light's radiance SH; then every entity's lights placed into the field's
//       SphereLightGather. An entity whose transform is not finite, or whose samples do not
//       match its sphere count, is left out and named in SphericalLightField::errors.
//   spherical_lights.gather   reads Receiver, Transform, SphericalLightField,
//       SphericalLightSettingsResource; writes ReceiverLighting
//       Pass 2 (sphere_light_gather.h): the one-bounce irradiance at each receiver point,
//       published as ReceiverLighting::indirect (new shared array). An entity whose points all
//       lie beyond every light's reach (its points' bound against each light's radius /
//       min_sin) gets zeros without a gather. Entities are re-shaded whole,
//       round robin within the settings' point budget, as blockers.shade does. With `indirect`
//       off in the settings every entity's indirect term is cleared.
//   spherical_lights.terrain  reads Terrain, TerrainHorizons, SphericalLightField,
//       SphericalLightSettingsResource; writes TerrainLighting, SphericalLightTerrainState
//       (adds it to a terrain, structural)
//       The bounce on the terrain's texels near the lights (terrain_indirect.h; its own gather
//       with terrain_horizon), rows spread over `terrain_period` frames, added as indirect / pi to
//       what the systems before it published (register after add_blocker_systems: the blockers'
//       shadowed terrain).
// render_extract adds indirect / pi to the VertexLighting it draws (radiance per unit albedo).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/spherical_lights/reflector_lighting.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"
#include "penumbra/systems/terrain_shadow/log_wedge.h"

namespace penumbra::spherical_lights {

inline constexpr int kSystemBands = 4;  // = components::ReflectorRadiance::kBands

// Resource: how the system shades.
struct SphericalLightSettingsResource {
  SphereLightSettings settings;
  bool indirect = true;  // false: no indirect light (the HUD's toggle)
  // Receiver points shaded per frame (0: all), whole entities round robin (a new one at once).
  std::size_t receiver_budget = 2048;
  // Frames between two pass-1 updates of one reflector (1: every frame); reflectors take turns
  // (entity index modulo the period), a new one at once. Its lights follow its transform every
  // frame (the radiance SH is in its own frame); only the light it reflects lags.
  int reflect_period = 4;
  // Terrain texels: shaded where a light's sin(angular radius) is above this (nearer than
  // radius / terrain_min_sin), each reached row once every `terrain_period` frames.
  float terrain_min_sin = 0.15f;
  int terrain_period = 4;
  // The horizon rule for terrain texels: the ground around objects resting on it is where
  // EmitterHorizon::kClip is exact and the shrink loses a third (docs/spherical_light_accuracy.md).
  EmitterHorizon terrain_horizon = EmitterHorizon::kClip;
};

// Per terrain entity: what spherical_lights.terrain keeps between frames.
struct SphericalLightTerrainState {
  std::shared_ptr<const std::vector<glm::vec3>> input;      // what the systems before published
  std::shared_ptr<const std::vector<glm::vec3>> published;  // ours: input + indirect / pi
  std::vector<glm::vec3> indirect;                          // per texel, W/m^2
  std::size_t reached = 0;                                  // texels within reach
  std::uint64_t frame = 0;
};

// Resource: this frame's spherical lights, written by spherical_lights.reflect.
struct SphericalLightField {
  std::shared_ptr<SphereLightGather<kSystemBands>> gather;
  std::shared_ptr<SphereLightGather<kSystemBands>> terrain_gather;  // terrain_horizon's
  // components::LocalLightRouting kSphereLightGather: the local lights (emitting only) and every
  // blocker sphere of the frame (blocking only), for ReceiverLighting::local; else null.
  std::shared_ptr<SphereLightGather<kSystemBands>> local_gather;
  std::size_t local_lights = 0;  // local lights in local_gather this frame
  std::shared_ptr<const ReflectorLighting<kSystemBands>> lighting;  // cell sums, per direction set
  std::size_t lights = 0;                                           // spherical lights this frame
  std::size_t sample_points = 0;  // sample points lit this frame (pass 1)
  std::size_t receivers = 0;      // receiver points shaded this frame (pass 2)
  std::uint64_t cursor = 0;       // next receiving entity of the round robin
  std::uint64_t frame = 0;        // frames reflected (the reflect period's clock)
  std::vector<std::string> errors;
  // The terrain's log-SH wedges for its cast shadow on the sample points (built on first use).
  std::shared_ptr<const terrain_shadow::LogWedge<kSystemBands>> cast_wedges;
};

// Adds SphericalLightSettingsResource (with `settings`) and SphericalLightField when absent.
void emplace_spherical_light_resources(ecs::World& world, const SphereLightSettings& settings = {});
void add_spherical_light_systems(jobs::Schedule& schedule);

}  // namespace penumbra::spherical_lights
