// The terrain shadow system in the job graph. Three task systems, in this order:
//
//   terrain_shadow.visibility  reads Terrain, TerrainShadowSettings, writes TerrainShadowState,
//                              TerrainHorizons (adds them to a new terrain, structural)
//       Per Terrain entity: a new height field -> full update; version + 1 with an `edited`
//       rectangle -> update_edit (only what the edit can change); unchanged -> nothing.
//   terrain_shadow.lights      reads SphericalLight, Terrain, writes TerrainShadowState
//       Sum of the spherical lights' irradiance per texel, re-shaded per tile: only the tiles
//       where a change of the lights could show, worst first, at most a budget of texels per
//       frame (light_refresh.h); every tile again, within the budget, when the terrain changed.
//   terrain_shadow.compose     reads EnvironmentLight, TerrainShadowSettings, writes
//       TerrainShadowState, TerrainLighting: albedo-free outgoing radiance
//       (E_env + E_key + E_lights) / pi per texel, published as a new shared array
//       (render/packet.h) when any input changed. The environment's SH is rotated by rotation_z
//       and dotted with the stored transfer vectors. With EnvironmentSources::kKeyLights and
//       sources found in the map (EnvironmentLight::sources, systems/environment), each source
//       no wider than key_light_max_radius is a key light shadowed by the terrain's horizon in
//       its azimuth (TerrainShadowing::add_key_light) and the SH is the map without those (its
//       OEM, [Ambrosj16] sec. 4.2);
//       its horizons are swept again only when the light's azimuth moved by more than
//       key_light_step of its angular radius or the terrain changed.
//
// Each system runs tbb::parallel_for over rows of texels inside its task (the executor's
// arena), so the work is parallel over tiles even though the systems are sequential. The
// per-terrain state between frames is the TerrainShadowState component
// (terrain_shadow_state.h); the settings are the TerrainShadowSettings resource.
// Entities need Terrain and TerrainLighting (add it, empty, at creation); the environment is
// optional (absent: black). Spherical lights are world positions.
#pragma once

#include "penumbra/components/environment_light.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/terrain_shadow/environment_refresh.h"
#include "penumbra/systems/terrain_shadow/light_refresh.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::terrain_shadow {

// What the environment's detected sources become on the terrain (components/environment_light.h):
// kKeyLights: each a key light with the terrain's exact horizon in its azimuth, the rest of the
// map in SH ([Ambrosj16] ch. 4; Snyder and Nowrouzezahrai 2008).
using components::EnvironmentSources;

// Resource: how the system shades (config and light_refresh are read when a terrain first gets
// its TerrainShadowState; the rest every frame).
struct TerrainShadowSettings {
  TerrainShadowConfig config;
  LightRefreshConfig light_refresh;
  EnvironmentRefreshConfig environment_refresh;  // read with config, when a terrain gets its state
  EnvironmentSources sources = EnvironmentSources::kKeyLights;
  // A key light's horizons are swept again when its azimuth moved by more than this share of
  // its angular radius (the width of its penumbra; a point light: every move).
  float key_light_step = 0.25f;
  // Sources wider than this (radians; 0.2 = 11.5 degrees) stay in the SH: a glow over a third of
  // the sky is no directional light (docs/environment.md: suns come out 2.7-3.2 degrees, wide
  // bright areas 28-47).
  float key_light_max_radius = 0.2f;
};

// Adds the TerrainShadowSettings resource (with `config`) when absent.
void emplace_terrain_shadow_resources(ecs::World& world, const TerrainShadowConfig& config = {},
                                      const LightRefreshConfig& light_refresh = {});

// Registers the three systems above.
void add_terrain_shadow_systems(jobs::Schedule& schedule);

}  // namespace penumbra::terrain_shadow
