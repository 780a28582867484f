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
//   terrain_shadow.compose     reads EnvironmentLight, writes TerrainShadowState,
//       TerrainLighting: albedo-free outgoing radiance (E_env + E_lights) / pi per texel,
//       published as a new shared array (render/packet.h) when any input changed. The
//       environment's SH is rotated by rotation_z and dotted with the stored transfer vectors.
//
// Each system runs tbb::parallel_for over rows of texels inside its task (the executor's
// arena), so the work is parallel over tiles even though the systems are sequential. The
// per-terrain state between frames is the TerrainShadowState component
// (terrain_shadow_state.h); the settings are the TerrainShadowSettings resource.
// Entities need Terrain and TerrainLighting (add it, empty, at creation); the environment is
// optional (absent: black). Spherical lights are world positions.
#pragma once

#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/terrain_shadow/light_refresh.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::terrain_shadow {

// Resource: how the system shades (read when a terrain first gets its TerrainShadowState).
struct TerrainShadowSettings {
  TerrainShadowConfig config;
  LightRefreshConfig light_refresh;
};

// Adds the TerrainShadowSettings resource (with `config`) when absent.
void emplace_terrain_shadow_resources(ecs::World& world, const TerrainShadowConfig& config = {},
                                      const LightRefreshConfig& light_refresh = {});

// Registers the three systems above.
void add_terrain_shadow_systems(jobs::Schedule& schedule);

}  // namespace penumbra::terrain_shadow
