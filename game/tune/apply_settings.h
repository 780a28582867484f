// A tuned settings file's values as the systems' own settings (tuned_settings.h, docs/tune.md):
// for engines that drive the method classes without the ECS, and for penumbra_play --settings,
// which applies them to the settings resources and the demo's configuration.
// SH bands: the ECS systems run at 4 bands (terrain_shadow's TerrainShadowing<4>,
// blocker_accumulation::kSystemBands); the tuned band count is for the method classes
// (TerrainShadowing<N>, BlockerAccumulation<N>), which callers instantiate themselves.
// Threading: pure functions, except apply_to_world (one thread, between frames).
#pragma once

#include <filesystem>

#include "penumbra/ecs/world.h"
#include "penumbra/settings/tuned_settings.h"
#include "penumbra/systems/blocker_accumulation/blocker_accumulation.h"
#include "penumbra/systems/spherical_lights/reflector_samples.h"
#include "penumbra/systems/spherical_lights/sphere_light_gather.h"
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

namespace penumbra::tune {

struct SystemSettings {
  terrain_shadow::TerrainShadowConfig terrain;
  int terrain_bands = 4;
  blocker_accumulation::BlockerSettings blockers;
  int blocker_bands = 4;
  int spheres_per_object = 16;
  spherical_lights::SphereLightSettings spherical_lights;
  spherical_lights::ReflectorSettings reflectors;
  spherical_lights::EmitterHorizon ground_horizon = spherical_lights::EmitterHorizon::kClip;
  int probes_per_side = 12;
  float probe_spacing = 10;
  settings::TunedSettings source;  // what these came from (result.tuned says what was searched)
};

SystemSettings system_settings(const settings::TunedSettings& s);
// settings::load_settings(file), then system_settings (assets::LoadError naming the file).
SystemSettings load_system_settings(const std::filesystem::path& file);

// The main job's demo (game/terrain_demo.h) for the systems the file tuned: the terrain's
// horizons, azimuths and pyramid step into `terrain`, the boulders' spheres per model, the
// probe grid's probes per side.
void apply_to_demo(const SystemSettings& s, terrain_shadow::TerrainShadowConfig& terrain,
                   int& spheres_per_object, int& probes_per_side);

// Sets, for each system the file tuned, the tuned fields of the settings resources present in
// `world` (TerrainShadowSettings::config: method, azimuths, pyramid step;
// BlockerSettingsResource::settings.blocker.epsilon; SphericalLightSettingsResource: blocking,
// terrain_horizon; not the gather, the hierarchy cut: the main job's gather is per receiver);
// every other field keeps its value. The
// terrain's config is read when a terrain first gets its state: call before the first frame.
void apply_to_world(const SystemSettings& s, ecs::World& world);

}  // namespace penumbra::tune
