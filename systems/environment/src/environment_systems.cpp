#include "penumbra/systems/environment/environment_systems.h"

#include <exception>

#include "penumbra/components/environment_light.h"
#include "penumbra/systems/environment/environment_light_update.h"

namespace penumbra::environment {
namespace {

void update_sources(ecs::World& w) {
  components::EnvironmentLight* light = w.try_resource<components::EnvironmentLight>();
  if (light) jobs::report_item(sources_stale(*light));  // a map whose sources are found: skipped
  if (!light || !sources_stale(*light)) return;
  EnvironmentSettings& s = w.resource<EnvironmentSettings>();
  ++s.detections;
  try {
    update_environment_light(*light, s.detection);  // [Ambrosj16] ch. 4
    s.error.clear();
  } catch (const std::exception& e) {
    // No sources for this map: the readers fall back to its SH alone; not retried until the
    // map changes.
    light->sources.clear();
    light->oem_sh.clear();
    light->oem_sh3.clear();
    light->sources_version = light->version;
    s.error = e.what();
  }
}

}  // namespace

void emplace_environment_resources(ecs::World& world, const DetectionSettings& detection) {
  if (!world.try_resource<EnvironmentSettings>())
    world.emplace_resource<EnvironmentSettings>(EnvironmentSettings{detection, {}, 0});
}

void add_environment_systems(jobs::Schedule& schedule) {
  schedule
      .add_task("environment.sources",
                [](jobs::SystemContext& ctx) { update_sources(ctx.world()); })
      .writes<components::EnvironmentLight, EnvironmentSettings>();
}

}  // namespace penumbra::environment
