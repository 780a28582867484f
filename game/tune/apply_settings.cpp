#include "apply_settings.h"

#include "penumbra/systems/blocker_accumulation/blocker_systems.h"
#include "penumbra/systems/spherical_lights/spherical_light_systems.h"
#include "penumbra/systems/terrain_shadow/terrain_shadow_systems.h"

namespace penumbra::tune {

SystemSettings system_settings(const settings::TunedSettings& s) {
  SystemSettings o;
  o.terrain.method = s.terrain.horizon == "march" ? terrain_shadow::HorizonMethod::kMarch
                                                  : terrain_shadow::HorizonMethod::kSweep;
  o.terrain.azimuths = s.terrain.azimuths;
  o.terrain.pyramid.level_step = s.terrain.level_step;
  o.terrain_bands = s.terrain.bands;
  o.blockers.blocker.epsilon = s.blockers.epsilon;
  o.blocker_bands = s.blockers.bands;
  o.spheres_per_object = s.blockers.spheres_per_object;
  o.spherical_lights.blocking = s.spherical_lights.blocking == "per_object"
                                    ? spherical_lights::SlBlocking::kPerObject
                                    : spherical_lights::SlBlocking::kPerSphere;
  o.spherical_lights.blocker = o.blockers.blocker;
  o.reflectors.geodesic_frequency = s.spherical_lights.directions_frequency;
  o.ground_horizon = s.spherical_lights.horizon == "shrink"
                         ? spherical_lights::EmitterHorizon::kShrink
                         : spherical_lights::EmitterHorizon::kClip;
  o.probes_per_side = s.probes.probes_per_side;
  o.probe_spacing = s.probes.spacing;
  o.source = s;
  return o;
}

SystemSettings load_system_settings(const std::filesystem::path& file) {
  return system_settings(settings::load_settings(file));
}

void apply_to_demo(const SystemSettings& s, terrain_shadow::TerrainShadowConfig& terrain,
                   int& spheres_per_object, int& probes_per_side) {
  if (s.source.terrain.result.tuned) {
    terrain.method = s.terrain.method;
    terrain.azimuths = s.terrain.azimuths;
    terrain.pyramid = s.terrain.pyramid;
  }
  if (s.source.blockers.result.tuned) spheres_per_object = s.spheres_per_object;
  if (s.source.probes.result.tuned) probes_per_side = s.probes_per_side;
}

void apply_to_world(const SystemSettings& s, ecs::World& world) {
  auto* t = world.try_resource<terrain_shadow::TerrainShadowSettings>();
  if (t && s.source.terrain.result.tuned) {
    t->config.method = s.terrain.method;
    t->config.azimuths = s.terrain.azimuths;
    t->config.pyramid = s.terrain.pyramid;
  }
  auto* b = world.try_resource<blocker_accumulation::BlockerSettingsResource>();
  if (b && s.source.blockers.result.tuned) b->settings.blocker.epsilon = s.blockers.blocker.epsilon;
  auto* l = world.try_resource<spherical_lights::SphericalLightSettingsResource>();
  if (l && s.source.spherical_lights.result.tuned) {
    l->settings.blocking = s.spherical_lights.blocking;
    l->terrain_horizon = s.ground_horizon;
  }
}

}  // namespace penumbra::tune
