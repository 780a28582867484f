// The terrain shadow system in the job graph. Three task systems, in this order:
//
//   terrain_shadow.visibility  reads Terrain, writes TerrainShadowCache
//       Per Terrain entity: a new height field -> full update; version + 1 with an `edited`
//       rectangle -> update_edit (only what the edit can change); unchanged -> nothing.
//   terrain_shadow.lights      reads SphericalLight, Terrain, writes TerrainShadowCache
//       Sum of the spherical lights' irradiance per texel, re-shaded per tile: only the tiles
//       where a change of the lights could show, worst first, at most a budget of texels per
//       frame (light_refresh.h); every tile again, within the budget, when the terrain changed.
//   terrain_shadow.compose     reads EnvironmentLight, TerrainShadowCache, writes
//       TerrainLighting: albedo-free outgoing radiance (E_env + E_lights) / pi per texel,
//       published as a new shared array (render/packet.h) when any input changed. The
//       environment's SH is rotated by rotation_z and dotted with the stored transfer vectors.
//
// Each system runs tbb::parallel_for over rows of texels inside its task (the executor's
// arena), so the work is parallel over tiles even though the systems are sequential.
// Entities need Terrain and TerrainLighting (add it, empty, at creation); the environment is
// optional (absent: black). Spherical lights are world positions.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/ecs/entity.h"
#include "penumbra/ecs/world.h"
#include "penumbra/jobs/schedule.h"
#include "penumbra/systems/terrain_shadow/light_refresh.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::terrain_shadow {

inline constexpr int kSystemBands = sh::kDefaultBands;

// Resource: the per-terrain state the systems keep between frames.
struct TerrainShadowCache {
  struct Entry {
    ecs::Entity entity;
    std::unique_ptr<TerrainShadowing<kSystemBands>> shadowing;
    const assets::HeightField* field = nullptr;  // identity of the field last processed
    std::uint64_t version = 0;
    std::vector<glm::vec3> light_irradiance;  // sum over lights, W/m^2
    std::uint64_t visibility_stamp = 0;       // bumped when transfer changed
    std::uint64_t lights_stamp = 0;           // bumped when light_irradiance changed
    std::uint64_t composed_visibility = ~0ull, composed_lights = ~0ull;
    std::uint64_t composed_environment = ~0ull;
    float composed_rotation = 0;
    LightRefresh refresh;                      // which tiles the lights re-shade
    std::uint64_t refresh_visibility = ~0ull;  // visibility_stamp the refresh tiles were made for
    glm::vec3 refresh_origin{0.0f};
    UpdateStats last_update;  // of the latest visibility update (for overlays, benchmarks)
  };
  TerrainShadowConfig config;
  LightRefreshConfig light_refresh;
  std::vector<Entry> entries;
};

// Adds the TerrainShadowCache resource (with `config`) when absent.
void emplace_terrain_shadow_resources(ecs::World& world, const TerrainShadowConfig& config = {},
                                      const LightRefreshConfig& light_refresh = {});

// Registers the three systems above.
void add_terrain_shadow_systems(jobs::Schedule& schedule);

}  // namespace penumbra::terrain_shadow
