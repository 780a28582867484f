// TerrainShadowState: the terrain shadow system's per-entity state between frames, kept in
// component storage beside the entity's Terrain (as EnTT and Bevy keep per-entity data), not in
// a side table. terrain_shadow.visibility adds it (a deferred command, applied before
// terrain_shadow.lights) the first frame it sees a Terrain with heights, and removes it when the
// Terrain goes; it goes with the entity. Written only by the system's three tasks
// (terrain_shadow_systems.h); other code reads what the system publishes: TerrainLighting and
// TerrainHorizons. Tests read it to check what each frame skipped.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "penumbra/ecs/entity.h"
#include "penumbra/sh/basis.h"
#include "penumbra/systems/terrain_shadow/environment_refresh.h"
#include "penumbra/systems/terrain_shadow/light_refresh.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::terrain_shadow {

// The system's SH bands. 3: with the exact transfer (TransferMethod::kExact) 3 bands are the
// most accurate on average over the accuracy scenes and maps (2.53% against 3.07% at 4,
// docs/terrain_shadow.md "SH bands": the sun's ringing makes band 3 hurt), equal to 4 with the
// sun as a key light (1.10% both), and cheaper. The environment's 4-band SH is truncated.
inline constexpr int kSystemBands = 3;
static_assert(kSystemBands <= sh::kDefaultBands);

struct TerrainShadowState {
  // Shared with TerrainHorizons, which aliases its horizons and normals.
  std::shared_ptr<TerrainShadowing<kSystemBands>> shadowing;
  const data::HeightField* field = nullptr;  // identity of the field last processed
  std::uint64_t version = 0;
  std::vector<glm::vec3> light_irradiance;  // sum over lights, W/m^2
  std::uint64_t visibility_stamp = 0;       // bumped when transfer changed
  std::uint64_t lights_stamp = 0;           // bumped when light_irradiance changed
  std::uint64_t composed_visibility = ~0ull, composed_lights = ~0ull;
  std::uint64_t composed_environment = ~0ull;
  float composed_rotation = 0;
  float composed_intensity = 1;  // EnvironmentLight::intensity the composed values have
  // Key lights (the environment's sources, compose): per source its horizons and the azimuth
  // and visibility_stamp they were swept for.
  struct KeyLight {
    float phi = 0;
    std::uint64_t visibility = ~0ull;
    std::vector<float> horizons;
  };
  std::vector<KeyLight> key_lights;
  std::uint64_t key_horizons_generation = 0;  // bumped whenever a key light's horizons are swept
  std::vector<std::size_t> key_sources;       // this frame's key lights: their source indices
  // The environment's share per texel (SH + key lights, W/m^2), re-shaded per tile
  // (environment_refresh.h), and the composed radiance last published.
  std::vector<glm::vec3> environment_irradiance;
  std::vector<glm::vec3> composed;
  EnvironmentRefresh environment_refresh;
  std::vector<TexelRect> lights_dirty;     // tiles the lights re-shaded since the last compose
  std::uint64_t composed_sources = ~0ull;  // (sources_version + 1) << 8 | key-light mask
  LightRefresh refresh;                    // which tiles the lights re-shade
  // Per spherical light (by entity), its own irradiance and, per refresh tile, the light as
  // that tile last shaded it: a re-shaded tile recomputes only the lights that changed there
  // (a moving orb among lit beacons re-shades the orb alone) and sums the layers, in light
  // order from zero, into light_irradiance. Cleared when the terrain changes.
  struct LightLayer {
    ecs::Entity entity;
    std::vector<glm::vec3> irradiance;      // empty until the light first shades a tile
    std::vector<LightSample> tile_samples;  // radius < 0: never shaded
  };
  std::vector<LightLayer> light_layers;
  std::size_t light_tile_shades = 0;         // the last re-shade's (tile, light) pairs recomputed
  std::uint64_t refresh_visibility = ~0ull;  // visibility_stamp the refresh tiles were made for
  glm::vec3 refresh_origin{0.0f};
  UpdateStats last_update;  // of the latest visibility update (for overlays, benchmarks)
};

}  // namespace penumbra::terrain_shadow
